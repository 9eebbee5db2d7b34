//! The front ends: the window (glutin + winit, in place of the tutorial's GLFW), headless rendering
//! (EGL + an offscreen target, which also serves `--bench`, screenshots and the tests) and, in a
//! wasm32 build, the browser page (`web`; the window and headless rendering are left out there).
//! Each makes its context, translates its platform's input into the host's [`events::Event`]s,
//! presents the frames the host draws and does what the host asks back ([`events::Request`]): the
//! scene host ([`host::SceneHost`]) runs every scene alike, so a test's pixels are the window's
//! pixels.
//!
//! The files, each using only those above it: [`keys`] (key names, the front ends' own keys and the
//! key lists), [`frame_clock`], [`events`], [`tour_pane`] and [`panel`] (egui over the frame), [`host`], then the
//! front ends; [`page_contract`] (the page's URL) and [`page_input`] (the page's DOM names) are the
//! page's, compiled natively too so that their tests run with the others.

pub mod events;
pub mod frame_clock;
#[cfg(not(target_arch = "wasm32"))]
pub mod headless;
pub mod host;
pub mod keys;
pub mod page_contract;
pub mod page_input;
pub mod panel;
pub mod tour_pane;
#[cfg(target_arch = "wasm32")]
pub mod web;
#[cfg(not(target_arch = "wasm32"))]
pub mod window;
