//! The page's entry point: wasm-bindgen calls `start` once the module is loaded; everything else is
//! the library's browser front end (`tutorial13::frontends::web`).

use wasm_bindgen::prelude::*;

#[wasm_bindgen(start)]
pub fn start() {
    tutorial13::frontends::web::start();
}
