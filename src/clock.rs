//! The clock the load timings and the frame timer read: std's `Instant` natively; in the browser
//! (wasm32), where std's panics, one over `performance.now()`.

#[cfg(not(target_arch = "wasm32"))]
pub use std::time::Instant;
#[cfg(target_arch = "wasm32")]
pub use web_time::Instant;
