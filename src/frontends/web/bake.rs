//! The page's bake panel (`#bake` in index.html): HIGH's files and LOW's dropped on their two slots
//! (or chosen there), `tutorial13 bake`'s settings, and the bake itself in a Web Worker
//! (web/bake-worker.js running this same module's `bake`, web/src/bake.rs), so that the page's
//! frames keep coming while it runs. A progress bar; Cancel terminates the worker; the map is drawn
//! on LOW as soon as it is done (the cylinder scene with LOW as its model and the map as its normal
//! map, in the frame it was baked for: the compare key K at hand), and Save downloads the PNG.
//!
//! A worker is started ahead of each bake, once a slot has taken its files: it loads the module and
//! warms it up with a small bake of its own (web/src/bake.rs `warm_up`) while the learner sets the
//! bake up, so that Bake starts at once on the browser's best code.
//!
//! The worker gets the command's own arguments (`high/H.obj low/L.obj -o L_normal.png --size …`),
//! which the panel shows as the native command that makes the same map.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{DragEvent, Event, HtmlInputElement, HtmlSelectElement, MessageEvent};

use super::{clear_error, element, show_error, Page};
use crate::clock::Instant;
use crate::model::Format;
use crate::scenes::cylinder::{CylinderFiles, TANGENTS};
use crate::scenes::SceneOptions;
use crate::tangent_source::TangentSource;

/// HIGH (the detailed model) or LOW (the one whose UVs the map fills).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    High,
    Low,
}

impl Role {
    fn name(self) -> &'static str {
        match self {
            Role::High => "HIGH",
            Role::Low => "LOW",
        }
    }

    /// Where its files are kept (in the worker, and LOW's in the page to draw it): messages name
    /// them so, `low/crate.obj`.
    fn folder(self) -> &'static str {
        match self {
            Role::High => "high",
            Role::Low => "low",
        }
    }

    /// Its slot's element.
    fn slot(self) -> &'static str {
        match self {
            Role::High => "bake-high",
            Role::Low => "bake-low",
        }
    }
}

/// A slot's files (names and bytes) and the model among them.
struct Dropped {
    files: Vec<(String, Vec<u8>)>,
    model: String,
}

impl Dropped {
    /// Where the model is kept (see [`Role::folder`]).
    fn model_path(&self, role: Role) -> PathBuf {
        Path::new(role.folder()).join(&self.model)
    }
}

/// The bake that runs: its worker, the handlers it calls (kept alive while it runs), and what
/// drawing its map needs.
struct Running {
    worker: web_sys::Worker,
    _handlers: [Handler; 2],
    start: Instant,
    /// The page's frames drawn when it started (`data-frames`).
    frames: u32,
    /// LOW as the page keeps it, and where its map goes.
    low: PathBuf,
    map: PathBuf,
    /// The frame the map is baked for, drawn with.
    tangents: TangentSource,
}

/// The panel's state.
#[derive(Default)]
struct Panel {
    high: Option<Dropped>,
    low: Option<Dropped>,
    running: Option<Running>,
    /// A worker started ahead of the next bake (once a slot has taken files, and again after each
    /// bake), its module already loading, so that Bake does not wait for it; with the handler
    /// that drops it if it fails to load (a fresh one then says why).
    spare: Option<(web_sys::Worker, Handler)>,
    /// The last map's object URL (Save's link), revoked when another replaces it.
    saved: Option<String>,
}

type Shared = Rc<RefCell<Panel>>;

/// A DOM event handler kept alive while the bake runs.
type Handler = Closure<dyn FnMut(Event)>;

/// Listens to the panel's slots and buttons, if the page has the panel.
pub(super) fn listen(page: &Rc<RefCell<Page>>) -> Result<(), String> {
    if element("bake").is_none() {
        return Ok(());
    }
    let panel = Shared::default();
    for role in [Role::High, Role::Low] {
        listen_to_slot(role, &panel)?;
    }
    let (started, page) = (panel.clone(), page.clone());
    on("bake-start", "click", move |_| start(&started, &page))?;
    on("bake-cancel", "click", move |_| cancel(&panel))
}

/// `handle` on `kind` events of the element `id`.
fn on(id: &str, kind: &str, handle: impl FnMut(Event) + 'static) -> Result<(), String> {
    let target = element(id).ok_or_else(|| format!("the page has no #{id}"))?;
    let closure = Closure::<dyn FnMut(Event)>::new(handle);
    target
        .add_event_listener_with_callback(kind, closure.as_ref().unchecked_ref())
        .map_err(|_| format!("cannot listen to {kind} on #{id}"))?;
    // The panel lives as long as the tab.
    closure.forget();
    Ok(())
}

/// A slot takes the files dropped on it or chosen with its file input.
fn listen_to_slot(role: Role, panel: &Shared) -> Result<(), String> {
    on(role.slot(), "dragover", |event| event.prevent_default())?;
    let dropped = panel.clone();
    on(role.slot(), "drop", move |event| {
        event.prevent_default();
        let files = event.dyn_ref::<DragEvent>().and_then(|e| e.data_transfer());
        if let Some(list) = files.and_then(|d| d.files()) {
            take(role, list, &dropped);
        }
    })?;
    let chosen = panel.clone();
    on(&format!("{}-files", role.slot()), "change", move |event| {
        let input = event
            .target()
            .and_then(|t| t.dyn_into::<HtmlInputElement>().ok());
        if let Some(list) = input.and_then(|i| i.files()) {
            take(role, list, &chosen);
        }
    })
}

/// Reads `list` into `role`'s slot: the model among the files (one `.obj`, `.gltf` or `.glb`) and
/// those it names. A list with no model, or two, is a notice and leaves the slot as it was.
fn take(role: Role, list: web_sys::FileList, panel: &Shared) {
    let files: Vec<web_sys::File> = (0..list.length()).filter_map(|i| list.get(i)).collect();
    let panel = panel.clone();
    wasm_bindgen_futures::spawn_local(async move {
        clear_error();
        let files = match read_files(files).await {
            Ok(files) => files,
            Err(line) => return show_error(&line),
        };
        let names: Vec<&str> = files.iter().map(|(name, _)| name.as_str()).collect();
        let models: Vec<&str> = (names.iter().copied())
            .filter(|name| Format::of(Path::new(name)).is_some())
            .collect();
        let model = match models[..] {
            [model] => model.to_owned(),
            [] => {
                return show_error(&format!(
                    "bake: {} is no model (drop {} model on {}, with its .mtl and maps)",
                    names.join(", "),
                    Format::listed(),
                    role.name()
                ))
            }
            _ => {
                return show_error(&format!(
                    "bake: {} are {} models: drop one on {}",
                    models.join(", "),
                    models.len(),
                    role.name()
                ))
            }
        };
        set_text(&format!("{}-names", role.slot()), &names.join(", "));
        let dropped = Dropped { files, model };
        match role {
            Role::High => panel.borrow_mut().high = Some(dropped),
            Role::Low => panel.borrow_mut().low = Some(dropped),
        }
        keep_spare(&panel);
    });
}

/// The names and bytes of `files`; an error names the one that cannot be read.
async fn read_files(files: Vec<web_sys::File>) -> Result<Vec<(String, Vec<u8>)>, String> {
    let mut read = Vec::new();
    for file in files {
        let name = file.name();
        match wasm_bindgen_futures::JsFuture::from(file.array_buffer()).await {
            Ok(buffer) => read.push((name, js_sys::Uint8Array::new(&buffer).to_vec())),
            Err(_) => return Err(format!("{name}: cannot be read")),
        }
    }
    Ok(read)
}

/// The Bake button: the worker started on both slots' files with the panel's settings.
fn start(panel: &Shared, page: &Rc<RefCell<Page>>) {
    clear_error();
    if panel.borrow().running.is_some() {
        return;
    }
    let (args, tangents, low, map) = {
        let state = panel.borrow();
        let (Some(high), Some(low)) = (&state.high, &state.low) else {
            let missing = match (&state.high, &state.low) {
                (None, None) => "HIGH's and LOW's",
                (None, Some(_)) => "HIGH's",
                _ => "LOW's",
            };
            return show_error(&format!(
                "bake: drop {missing} files on their slots first (a bake needs both models)"
            ));
        };
        let map = Path::new(Role::Low.folder()).join(map_name(&low.model));
        let (args, tangents) = arguments(
            &high.model_path(Role::High),
            &low.model_path(Role::Low),
            &map,
        );
        (args, tangents, low.model_path(Role::Low), map)
    };
    set_text(
        "bake-command",
        &format!("the same as: tutorial13 bake {}", shown(&args)),
    );
    match spawn(panel, page, &args) {
        Ok((worker, handlers)) => {
            panel.borrow_mut().running = Some(Running {
                worker,
                _handlers: handlers,
                start: Instant::now(),
                frames: frames_drawn(),
                low,
                map,
                tangents,
            });
            set_state("running");
            set_progress("starting the worker", 0.0);
        }
        Err(line) => show_error(&line),
    }
}

/// The map's file name: LOW's stem and `_normal.png`.
fn map_name(low: &str) -> String {
    let stem = Path::new(low).file_stem().unwrap_or_default();
    format!("{}_normal.png", stem.to_string_lossy())
}

/// `tutorial13 bake`'s arguments for the panel's settings, and the frame they bake for.
fn arguments(high: &Path, low: &Path, map: &Path) -> (Vec<String>, TangentSource) {
    let mut args: Vec<String> = [high, low, Path::new("-o"), map]
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    let tangents = select_value("bake-tangents");
    for (flag, value) in [
        ("--size", select_value("bake-size")),
        ("--samples", select_value("bake-samples")),
        ("--tangents", tangents.clone()),
        ("--extrusion", input_value("bake-extrusion")),
        ("--max-distance", input_value("bake-max-distance")),
    ] {
        // An empty field is the command's default.
        if !value.is_empty() {
            args.extend([flag.to_string(), value]);
        }
    }
    let source = match tangents.as_str() {
        "tutorial" => TangentSource::Tutorial,
        "file" => TangentSource::File,
        _ => TangentSource::MikkTSpace,
    };
    (args, source)
}

/// The arguments as a command line shows them (the folders the page keeps the files in dropped).
fn shown(args: &[String]) -> String {
    let bare = |a: &String| {
        let a = a
            .strip_prefix("high/")
            .or(a.strip_prefix("low/"))
            .unwrap_or(a);
        if a.contains(' ') {
            format!("'{a}'")
        } else {
            a.to_string()
        }
    };
    args.iter().map(bare).collect::<Vec<_>>().join(" ")
}

/// A bake worker (web/bake-worker.js), loading the page's module as it starts.
fn new_worker() -> Result<web_sys::Worker, String> {
    let options = web_sys::WorkerOptions::new();
    options.set_type(web_sys::WorkerType::Module);
    web_sys::Worker::new_with_options("bake-worker.js", &options)
        .map_err(|_| "bake: this browser cannot start a module worker (bake-worker.js)".into())
}

/// Starts the spare worker ([`Panel::spare`]) if there is none and no bake runs. A worker that
/// cannot be started here is left to Bake, which says why.
fn keep_spare(panel: &Shared) {
    {
        let state = panel.borrow();
        if state.spare.is_some() || state.running.is_some() {
            return;
        }
    }
    let Ok(worker) = new_worker() else { return };
    let dropped = Rc::downgrade(panel);
    let on_error = Handler::new(move |_: Event| {
        if let Some(panel) = dropped.upgrade() {
            panel.borrow_mut().spare = None;
        }
    });
    worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
    panel.borrow_mut().spare = Some((worker, on_error));
}

/// The worker (the spare, or a new one), sent both slots' files and `args`, and its two handlers
/// (a message; a failure to load it).
fn spawn(
    panel: &Shared,
    page: &Rc<RefCell<Page>>,
    args: &[String],
) -> Result<(web_sys::Worker, [Handler; 2]), String> {
    let spare = panel.borrow_mut().spare.take();
    // The spare's own handler lives until the bake's replace it.
    let (worker, _spare_handler) = match spare {
        Some((worker, handler)) => (worker, Some(handler)),
        None => (new_worker()?, None),
    };
    let (answered, page) = (panel.clone(), page.clone());
    let on_message = Handler::new(move |event: Event| {
        if let Some(event) = event.dyn_ref::<MessageEvent>() {
            answer(&answered, &page, &event.data());
        }
    });
    let failed = panel.clone();
    let on_error = Handler::new(move |_: Event| {
        fail(
            &failed,
            "bake: the worker failed to load (bake-worker.js, tutorial13.js)",
        );
    });
    worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
    worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
    let (files, transfer) = (js_sys::Array::new(), js_sys::Array::new());
    let state = panel.borrow();
    for (role, dropped) in [(Role::High, &state.high), (Role::Low, &state.low)] {
        for (name, bytes) in dropped.iter().flat_map(|d| &d.files) {
            let path = format!("{}/{name}", role.folder());
            let bytes = js_sys::Uint8Array::from(bytes.as_slice());
            transfer.push(&bytes.buffer());
            files.push(&js_sys::Array::of2(&path.into(), &bytes));
        }
    }
    let message = js_sys::Object::new();
    let args: js_sys::Array = args.iter().map(|a| JsValue::from_str(a)).collect();
    let _ = js_sys::Reflect::set(&message, &"files".into(), &files);
    let _ = js_sys::Reflect::set(&message, &"args".into(), &args);
    if worker
        .post_message_with_transfer(&message, &transfer)
        .is_err()
    {
        // Not left running (the spare had started its warm-up).
        worker.terminate();
        return Err("bake: the files cannot be sent to the worker".into());
    }
    Ok((worker, [on_message, on_error]))
}

/// What the worker says: its progress, its map, or its error.
fn answer(panel: &Shared, page: &Rc<RefCell<Page>>, data: &JsValue) {
    let field = |key: &str| {
        js_sys::Reflect::get(data, &key.into())
            .ok()
            .filter(|v| !v.is_undefined())
    };
    if let Some(progress) = field("progress") {
        let progress = js_sys::Array::from(&progress);
        let stage = progress.get(0).as_string().unwrap_or_default();
        set_progress(&stage, progress.get(1).as_f64().unwrap_or(0.0));
    } else if let Some(error) = field("error") {
        fail(panel, &error.as_string().unwrap_or_default());
    } else if let Some(done) = field("done") {
        let Some(running) = panel.borrow_mut().running.take() else {
            return;
        };
        running.worker.terminate();
        finish(panel, page, running, &done);
    }
}

/// The map is in: kept, offered for saving, and drawn on LOW.
fn finish(panel: &Shared, page: &Rc<RefCell<Page>>, running: Running, done: &JsValue) {
    let seconds = running.start.elapsed().as_secs_f64();
    let get = |key: &str| js_sys::Reflect::get(done, &key.into()).unwrap_or_default();
    let map = js_sys::Uint8Array::new(&get("map"));
    let report = get("report").as_string().unwrap_or_default();
    let worker_seconds = get("seconds").as_f64().unwrap_or(f64::NAN);
    set_state("done");
    if let Some(bake) = element("bake") {
        let _ = bake.set_attribute("data-bake-ms", &format!("{:.0}", seconds * 1000.0));
        let _ = bake.set_attribute("data-worker-ms", &format!("{:.0}", worker_seconds * 1000.0));
        let during = format!("{} {}", running.frames, frames_drawn());
        let _ = bake.set_attribute("data-frames-during", &during);
    }
    set_progress(
        &format!("baked in {seconds:.2} s (the worker's bake {worker_seconds:.2} s)"),
        1.0,
    );
    set_text("bake-report", &report);
    offer(panel, &running.map, &map);
    // LOW's files, and the map beside them, where the page's loaders read them.
    for (name, bytes) in panel.borrow().low.iter().flat_map(|d| &d.files) {
        crate::files::provide(&Path::new(Role::Low.folder()).join(name), bytes.clone());
    }
    crate::files::provide(&running.map, map.to_vec());
    let page = page.clone();
    wasm_bindgen_futures::spawn_local(async move {
        let scene = crate::scenes::open_file(&running.low, &mut SceneOptions::default());
        if let Ok(scene) = scene {
            if let Err(e) = super::fetch_assets(scene).await {
                return show_error(&e);
            }
        }
        let (map, tangents) = (running.map, running.tangents);
        let opened = page
            .borrow_mut()
            .host
            .open_file_with(&running.low, |options| {
                options.get_mut::<CylinderFiles>().maps.normal = Some(map);
                options.start(TANGENTS.to(tangents));
            });
        if let Err(e) = opened {
            show_error(&e.to_string());
        }
    });
    keep_spare(panel);
}

/// Save's link to `map`, named as `path`'s file.
fn offer(panel: &Shared, path: &Path, map: &js_sys::Uint8Array) {
    let Some(link) =
        element("bake-save").and_then(|e| e.dyn_into::<web_sys::HtmlAnchorElement>().ok())
    else {
        return;
    };
    let parts = js_sys::Array::of1(map);
    let kind = web_sys::BlobPropertyBag::new();
    kind.set_type("image/png");
    let url = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &kind)
        .and_then(|blob| web_sys::Url::create_object_url_with_blob(&blob));
    let Ok(url) = url else {
        return show_error("bake: the map cannot be offered for saving");
    };
    if let Some(old) = panel.borrow_mut().saved.replace(url.clone()) {
        let _ = web_sys::Url::revoke_object_url(&old);
    }
    link.set_href(&url);
    link.set_download(&path.file_name().unwrap_or_default().to_string_lossy());
    link.set_hidden(false);
}

/// The bake ends with `line` (the command's error) on the page.
fn fail(panel: &Shared, line: &str) {
    // The first line says what went wrong (a trap after a panic sends a second).
    let Some(running) = panel.borrow_mut().running.take() else {
        return;
    };
    running.worker.terminate();
    set_state("failed");
    set_progress("failed", 0.0);
    show_error(line);
    keep_spare(panel);
}

/// Cancel: the worker terminated, its bake with it.
fn cancel(panel: &Shared) {
    let Some(running) = panel.borrow_mut().running.take() else {
        return;
    };
    running.worker.terminate();
    set_state("cancelled");
    set_progress("cancelled", 0.0);
    keep_spare(panel);
}

/// `#bake`'s `data-state` (the tests wait for it), the buttons as it allows.
fn set_state(state: &str) {
    if let Some(bake) = element("bake") {
        let _ = bake.set_attribute("data-state", state);
    }
    let running = state == "running";
    for (id, disabled) in [("bake-start", running), ("bake-cancel", !running)] {
        if let Some(button) = element(id) {
            let _ = match disabled {
                true => button.set_attribute("disabled", ""),
                false => button.remove_attribute("disabled"),
            };
        }
    }
}

/// The progress bar at `share` with `stage` beside it.
fn set_progress(stage: &str, share: f64) {
    if let Some(bar) = element("bake-progress") {
        let _ = bar.set_attribute("value", &format!("{share:.3}"));
    }
    let text = match stage {
        "tracing rays" => format!("{stage} {:.0} %", share * 100.0),
        _ => stage.to_string(),
    };
    set_text("bake-stage", &text);
}

fn set_text(id: &str, text: &str) {
    if let Some(e) = element(id) {
        e.set_text_content(Some(text));
    }
}

/// The canvas's `data-frames`: the frames the page has drawn.
fn frames_drawn() -> u32 {
    let frames = element("canvas").and_then(|c| c.get_attribute("data-frames"));
    frames.and_then(|f| f.parse().ok()).unwrap_or(0)
}

fn select_value(id: &str) -> String {
    let select = element(id).and_then(|e| e.dyn_into::<HtmlSelectElement>().ok());
    select.map(|s| s.value()).unwrap_or_default()
}

fn input_value(id: &str) -> String {
    let input = element(id).and_then(|e| e.dyn_into::<HtmlInputElement>().ok());
    input
        .map(|i| i.value().trim().to_string())
        .unwrap_or_default()
}
