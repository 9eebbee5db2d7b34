//! The bake worker's entry: web/bake-worker.js loads this same module in a Web Worker, hands it the
//! files the page's bake panel took (src/frontends/web/bake.rs) with [`provide_file`], and calls
//! [`bake`] with `tutorial13 bake`'s own arguments. The map is the command's (its code, its
//! settings, its encoder), run on the worker's one thread while the page's frames go on.

use std::cell::RefCell;
use std::path::Path;

use tutorial13::clock::Instant;
use tutorial13::tools::bake::{bake_map, coverage, encode, misses, scale_warning, BakeOptions};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// The page is told of the progress at most this often: a message each time.
const PROGRESS_EVERY_MS: f64 = 50.0;

/// The page's progress callback, and when and what it was last told.
struct Told {
    callback: js_sys::Function,
    at: Option<Instant>,
    stage: String,
}

thread_local! {
    /// The bake asks for a `Sync` callback, which a JS function is not: it is reached from here
    /// (the worker has one thread).
    static PROGRESS: RefCell<Option<Told>> = const { RefCell::new(None) };
}

/// Gives the bake a file at `path` (HIGH's files under `high/`, LOW's under `low/`).
#[wasm_bindgen]
pub fn provide_file(path: &str, bytes: Vec<u8>) {
    tutorial13::files::provide(Path::new(path), bytes);
}

/// Bakes a small pair once and throws its map away (a bumpy sphere of 9,216 triangles onto a UV
/// sphere of 256, 64², one ray a texel: a few tens of milliseconds). The browser first runs a
/// module's functions in code it compiles fast, and replaces a function's code with better code
/// only once it has run a while, from its next call on: the reader's and the BVH's few long calls
/// kept the first code through a whole bake, which then took about half as long again as the
/// same bake run a second time (BENCHMARKS.md). The worker calls this as it starts, before any
/// bake is asked of it. Its error (a pair that no longer bakes) fails the worker's bakes, so that
/// the browser tests see it.
#[wasm_bindgen]
pub fn warm_up() -> Result<(), String> {
    use tutorial13::assets::obj_text::{bumps, round, sphere_obj_text};
    let (high, low) = ("warm-up/high.obj", "warm-up/low.obj");
    let relief = bumps(0.02, 6.0);
    let high_text = sphere_obj_text(96, 48, &relief, false);
    tutorial13::files::provide(Path::new(high), high_text.into_bytes());
    let low_text = sphere_obj_text(16, 8, &round, false);
    tutorial13::files::provide(Path::new(low), low_text.into_bytes());
    let args: Vec<String> = [high, low, "-o", "warm-up/map.png", "--size", "64"]
        .map(String::from)
        .into();
    let failed = |e: tutorial13::Error| format!("bake: the worker's warm-up bake failed: {e}");
    let options = BakeOptions::from_args(&args)?;
    let (_, _, map) = bake_map(&options, None).map_err(failed)?;
    encode(&options, &map).map_err(failed)?;
    Ok(())
}

/// `tutorial13 bake ARGS`, the map returned (not written) as the bytes of the file `-o` names, with
/// the report's coverage and misses lines and the seconds it took (the files read from memory, the
/// bake, the file's bytes: the command's own time but for the disk); `progress(stage, share)` is
/// called as it goes, a new stage at once, the same stage at most every [`PROGRESS_EVERY_MS`]. An
/// error is the command's one line.
#[wasm_bindgen]
pub fn bake(args: Vec<String>, progress: js_sys::Function) -> Result<js_sys::Object, String> {
    let start = Instant::now();
    // A panic would end in a trap that says nothing: its message goes to the page first.
    std::panic::set_hook(Box::new(|info| {
        post_error(&format!("internal error: {info}"))
    }));
    PROGRESS.with(|p| {
        *p.borrow_mut() = Some(Told {
            callback: progress,
            at: None,
            stage: String::new(),
        })
    });
    let options = BakeOptions::from_args(&args)?;
    let (settings, files, map) = bake_map(&options, Some(&tell)).map_err(|e| e.to_string())?;
    tell("writing the PNG", 1.0);
    let file = encode(&options, &map).map_err(|e| e.to_string())?;
    let radius = files.low.placement.radius;
    let report = [
        Some(coverage(&settings, &map)),
        scale_warning(&options, &settings, radius),
    ]
    .into_iter()
    .flatten()
    .chain([misses(&options, &settings, &map.stats, files.scale)])
    .collect::<Vec<_>>()
    .join("; ");
    let result = js_sys::Object::new();
    let set = |key: &str, value: JsValue| js_sys::Reflect::set(&result, &key.into(), &value);
    let seconds = start.elapsed().as_secs_f64();
    set("map", js_sys::Uint8Array::from(file.as_slice()).into())
        .and_then(|_| set("report", report.into()))
        .and_then(|_| set("seconds", seconds.into()))
        .map_err(|_| "the bake's result cannot be handed back".to_string())?;
    Ok(result)
}

/// Calls the page's progress callback (see [`bake`]).
fn tell(stage: &str, share: f32) {
    PROGRESS.with(|p| {
        let mut p = p.borrow_mut();
        let Some(told) = p.as_mut() else { return };
        let due = told
            .at
            .is_none_or(|at| at.elapsed().as_secs_f64() * 1000.0 >= PROGRESS_EVERY_MS);
        if told.stage != stage || due {
            told.at = Some(Instant::now());
            told.stage = stage.to_string();
            let _ = told
                .callback
                .call2(&JsValue::NULL, &stage.into(), &share.into());
        }
    });
}

/// Posts `{ error: line }` to the page (the worker's `postMessage`).
fn post_error(line: &str) {
    let global = js_sys::global();
    let message = js_sys::Object::new();
    let _ = js_sys::Reflect::set(&message, &"error".into(), &line.into());
    if let Ok(post) = js_sys::Reflect::get(&global, &"postMessage".into()) {
        if let Ok(post) = post.dyn_into::<js_sys::Function>() {
            let _ = post.call1(&global, &message);
        }
    }
}
