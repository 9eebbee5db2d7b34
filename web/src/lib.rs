//! The page's entry points: wasm-bindgen calls `start` once the module is loaded; everything else is
//! the library's browser front end (`tutorial13::frontends::web`). The same module loaded in the
//! bake's Web Worker (web/bake-worker.js) starts nothing and runs [`bake::bake`].

mod bake;

use wasm_bindgen::prelude::*;

#[wasm_bindgen(start)]
pub fn start() {
    // A worker has no document: the module is there for the bake alone.
    if js_sys::Reflect::has(&js_sys::global(), &"document".into()) != Ok(true) {
        return;
    }
    tutorial13::frontends::web::start();
}
