//! The browser page (wasm32 only): a 1024×768 canvas with a WebGL2 context, driven through the same
//! [`SceneHost`] as the window and headless rendering, with the window's panel painted by egui on the
//! same context. `web/build.sh` builds it into `target/web/`.
//!
//! The page contract (tests and links use it) is [`PageContract`]: `index.html?scene=NAME&panel=off`
//! `&frames=N&s3tc=off`.
//!
//! The keys are the window's (scene keys, arrows, R, Enter, F1); a drag on the frame looks around
//! (a page cannot grab the cursor the way the window does without the user's leave). A dropped OBJ
//! with its MTL and maps opens as a dropped file does in the window. The page translates the DOM's
//! events for the host ([`input`]), presents the host's frames on the canvas and does what the host
//! asks of it: fetch a scene's files before it switches ([`Page::honour`]). Errors are one line on
//! the page, the same line the native program prints.

mod bake;
mod input;

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use glow::HasContext;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{HtmlCanvasElement, WebGl2RenderingContext};

use super::events::{AfterFetch, Event, FrameTime, Request};
use super::host::SceneHost;
use super::keys::FrontEnd;
use super::page_contract::{PageContract, FROZEN_STEP_S};
use crate::clock::Instant;
use crate::common::texture::WEBGL_S3TC_EXTENSION;
use crate::gl::current::GlContext;
use crate::gl::extensions::GlExtensions;
use crate::gl::offscreen::OffscreenTarget;
use crate::gl::{ContextInfo, Gl, Profile};
use crate::scenes::{SceneDescriptor, SceneOptions};
use crate::statistics::min_median;

/// The canvas's size: the tutorial's window.
pub const WIDTH: u32 = 1024;
pub const HEIGHT: u32 = 768;

/// Why the TBN lines have no immediate-mode variant here (the panel greys that choice with it).
pub const NO_IMMEDIATE_MODE: &str =
    "WebGL2 has no immediate mode (glBegin/glEnd): the TBN lines are drawn by the line shader";

/// The page's state: what the window's front end holds, minus the window.
struct Page {
    host: SceneHost,
    /// Where the scene and the panel are drawn, then copied onto the canvas: glow cannot read the
    /// canvas's own framebuffer back as a binding (it panics on WebGL's null framebuffer), and the
    /// panel and the compare view ask which framebuffer is bound.
    target: OffscreenTarget,
    /// Frames still to draw with time stepped (`frames=N`); `None`: run.
    frames_left: Option<u32>,
    /// With `frames=N`, each frame's time, drawn to completion (a one-texel read-back), in ms: the
    /// page's `data-frame-ms` is their median, as `--bench` times the native frames. The last
    /// [`FRAME_MS_KEPT`] only: the median is taken every frame, and a page may stay open for hours.
    frame_ms: Vec<f64>,
    /// With `frames=N`, the host's state after each frame that changed it
    /// ([`SceneHost::state_line`]): the tests' record of a walk through the tour.
    states: Vec<String>,
}

impl Page {
    /// One frame on the canvas, the panel over it if shown.
    fn frame(&mut self) {
        let start = Instant::now();
        self.target.bind();
        // The host asks for GL errors (a sync point here too) every frame of `frames=N`, else once
        // in a while.
        if let Err(e) = self.host.frame(true) {
            show_error(&e.to_string());
        }
        self.target.blit_columns_to(None, 0, WIDTH);
        // `frames=N` (the tests' and web/bench.py's frames) waits for each frame to be drawn, to
        // time it whole: WebGL's finish returns at once, a read-back cannot. A page that runs
        // never waits for the GPU: its panel shows the time between frames.
        if let Some(left) = &mut self.frames_left {
            *left = left.saturating_sub(1);
            let mut texel = [0u8; 4];
            // SAFETY: one texel of the bound target, into a buffer of its size.
            unsafe {
                self.host.gl().gl.read_pixels(
                    0,
                    0,
                    1,
                    1,
                    glow::RGBA,
                    glow::UNSIGNED_BYTE,
                    glow::PixelPackData::Slice(Some(&mut texel)),
                )
            };
            if self.frame_ms.len() == FRAME_MS_KEPT {
                self.frame_ms.remove(0);
            }
            self.frame_ms.push(start.elapsed().as_secs_f64() * 1000.0);
        }
    }

    /// An event for the host: an error goes on the page as its one line.
    fn event(&mut self, event: Event) {
        if let Err(e) = self.host.event(event) {
            show_error(&e.to_string());
        }
    }

    /// Does what the host asked of the page (`page` is this page, shared, for what comes back
    /// later): a scene's files fetched before it switches or opens a dropped model. The others are
    /// keys the page does not have (`HostKey::on_page`), a title it has no bar for, and a key list
    /// for a terminal.
    fn honour(&mut self, page: &Rc<RefCell<Page>>) {
        while let Some(request) = self.host.next_request() {
            match request {
                Request::Fetch { scene, then } => {
                    let page = page.clone();
                    wasm_bindgen_futures::spawn_local(async move {
                        match fetch_assets(scene).await {
                            Ok(()) => page.borrow_mut().fetched(then),
                            Err(e) => show_error(&e),
                        }
                    });
                }
                Request::Quit
                | Request::GrabCursor(_)
                | Request::Screenshot { .. }
                | Request::SetTitle(_)
                | Request::NewScene(_) => {}
            }
        }
    }

    /// The files a fetch asked for are in: the host does what waited for them (the last message
    /// goes; what this brings replaces it).
    fn fetched(&mut self, then: AfterFetch) {
        clear_error();
        if let Err(e) = self.host.fetched(then) {
            show_error(&e.to_string());
        }
    }

    /// Files dropped on the page: kept where the scenes' loaders read them; their paths returned,
    /// for the host to open the model among them.
    fn keep_dropped(files: Vec<(String, Vec<u8>)>) -> Vec<PathBuf> {
        let folder = Path::new("dropped");
        let mut paths = Vec::new();
        for (name, bytes) in files {
            let path = folder.join(&name);
            crate::files::provide(&path, bytes);
            paths.push(path);
        }
        paths
    }
}

/// What WebGL2 is, as [`ContextInfo`]: OpenGL ES 3.0 without profiles (read as core: no immediate
/// mode). The desktop queries `context_info` makes (`GL_CONTEXT_PROFILE_MASK`) do not exist here.
fn webgl2_info(gl: &glow::Context) -> ContextInfo {
    let mut extensions: Vec<String> = gl.supported_extensions().iter().cloned().collect();
    extensions.sort();
    // SAFETY: queries WebGL2 has.
    unsafe {
        ContextInfo {
            version: (3, 0),
            profile: Profile::Core,
            renderer: gl.get_parameter_string(glow::RENDERER),
            vendor: gl.get_parameter_string(glow::VENDOR),
            version_string: gl.get_parameter_string(glow::VERSION),
            extensions,
        }
    }
}

/// The page's one-line message (an error, or why there is no frame), in `#message`.
pub fn show_error(line: &str) {
    web_sys::console::warn_1(&JsValue::from_str(line));
    show_line(line, "error");
}

/// A line under the canvas: an error, or a notice (a warning the native program prints, such as a
/// map that falls back), below any already there.
fn show_line(line: &str, class: &str) {
    if let Some(element) = element("message") {
        let text = element.text_content().unwrap_or_default();
        let text = if text.is_empty() {
            line.to_owned()
        } else {
            format!("{text}\n{line}")
        };
        element.set_text_content(Some(&text));
        if element.get_attribute("class").as_deref() != Some("error") {
            let _ = element.set_attribute("class", class);
        }
    }
}

/// index.html's "loading…" taken off the message, any line after it kept.
fn drop_loading() {
    if let Some(element) = element("message") {
        let text = element.text_content().unwrap_or_default();
        if let Some(rest) = text.strip_prefix("loading…") {
            element.set_text_content(Some(rest.trim_start_matches('\n')));
        }
    }
}

fn clear_error() {
    if let Some(element) = element("message") {
        element.set_text_content(None);
        let _ = element.remove_attribute("class");
    }
}

fn element(id: &str) -> Option<web_sys::Element> {
    web_sys::window()?.document()?.get_element_by_id(id)
}

/// Starts the page: the context, the assets fetched, the scene built, then a frame per animation
/// frame. Every failure is one line on the page.
pub fn start() {
    // A panic would print a stack into the console and leave a frozen canvas: its message goes on
    // the page instead, as an error does.
    std::panic::set_hook(Box::new(|info| {
        let line = format!("internal error: {info}");
        web_sys::console::error_1(&JsValue::from_str(&line));
        // The first is the one that says what went wrong (a second may follow from the state the
        // first left).
        let shown = element("message").and_then(|e| e.text_content());
        // Lines accumulate (notices, then errors): look at each, not only the first.
        if !shown.is_some_and(|text| text.lines().any(|l| l.starts_with("internal error"))) {
            show_error(&line);
        }
    }));
    let _ = console_log();
    wasm_bindgen_futures::spawn_local(async {
        if let Err(line) = run().await {
            // "loading…" (index.html's) goes: the line says why nothing will load.
            drop_loading();
            show_error(&line);
        }
    });
}

/// `log`'s lines go to the browser's console (info and debug as console.log, warnings as
/// console.warn; errors are shown on the page by [`show_error`] and logged as warnings, so that a
/// console with an error means a bug, not bad input).
fn console_log() -> Result<(), log::SetLoggerError> {
    struct Console;
    impl log::Log for Console {
        fn enabled(&self, metadata: &log::Metadata) -> bool {
            metadata.level() <= log::Level::Info
        }
        fn log(&self, record: &log::Record) {
            if !self.enabled(record.metadata()) {
                return;
            }
            let text = record.args().to_string();
            let line = JsValue::from_str(&text);
            match record.level() {
                log::Level::Error | log::Level::Warn => {
                    web_sys::console::warn_1(&line);
                    show_line(&text, "warning");
                }
                _ => web_sys::console::log_1(&line),
            }
        }
        fn flush(&self) {}
    }
    log::set_logger(&Console).map(|()| log::set_max_level(log::LevelFilter::Info))
}

async fn run() -> Result<(), String> {
    let window = web_sys::window().ok_or("no window")?;
    let document = window.document().ok_or("no document")?;
    let contract = PageContract::parse(&window.location().search().unwrap_or_default())?;
    let canvas: HtmlCanvasElement = document
        .get_element_by_id("canvas")
        .and_then(|e| e.dyn_into().ok())
        .ok_or("the page has no <canvas id=\"canvas\">")?;
    let webgl2 = webgl2_context(&canvas)?;
    let descriptor = contract.scene;
    fetch_assets(descriptor).await?;

    // `Gl` is an `Arc` for the native threads' sake; the page has one thread.
    crate::gl::set_webgl2_context(&webgl2);
    #[allow(clippy::arc_with_non_send_sync)]
    let gl = Gl::new(glow::Context::from_webgl2_context(webgl2));
    let (info, extensions) = webgl2_extensions(&gl, &contract)?;
    let target = OffscreenTarget::new(&gl, WIDTH, HEIGHT).map_err(|e| e.to_string())?;
    target.bind();
    let context = GlContext {
        gl,
        info,
        extensions,
    };
    let mut host = SceneHost::new(
        context,
        descriptor,
        &SceneOptions::default(),
        (WIDTH, HEIGHT),
        FrontEnd::Page,
    )
    .map_err(|e| e.to_string())?;
    // `frames=N`: time stays at 0, but input still moves the camera (unlike `--frames N`, which
    // has none), each frame a step of FROZEN_STEP_S, so that a test's drag or arrow key gives a
    // frame the host predicts.
    if contract.frames.is_some() {
        host.set_time(FrameTime::Stepped(FROZEN_STEP_S));
    }
    if let Some(step) = contract.tour {
        host.set_step_state(step).map_err(|e| e.to_string())?;
    }
    host.show_panel().map_err(|e| e.to_string())?;
    host.set_panel_shown(contract.panel);
    let page = Rc::new(RefCell::new(Page {
        host,
        target,
        frames_left: contract.frames,
        frame_ms: Vec::new(),
        states: Vec::new(),
    }));
    FROZEN.with(|frozen| frozen.set(contract.frames.is_some()));
    input::listen(&window, &canvas, &page)?;
    bake::listen(&page)?;
    // "loading…" goes.
    clear_error();
    animate(page);
    Ok(())
}

/// The canvas sized for the scenes, and its WebGL2 context.
fn webgl2_context(canvas: &HtmlCanvasElement) -> Result<WebGl2RenderingContext, String> {
    canvas.set_width(WIDTH);
    canvas.set_height(HEIGHT);
    // No multisampling, as the tutorial's window; the frame is kept after it is shown, for
    // screenshots of `frames=N`.
    let attributes = js_sys::Object::new();
    for (key, value) in [("antialias", false), ("preserveDrawingBuffer", true)] {
        js_sys::Reflect::set(&attributes, &key.into(), &value.into())
            .map_err(|_| "cannot set the context's attributes")?;
    }
    canvas
        .get_context_with_context_options("webgl2", &attributes)
        .ok()
        .flatten()
        .and_then(|c| c.dyn_into().ok())
        .ok_or_else(|| {
            "this browser gives no WebGL2 context (the scenes need it): \
             try another browser, or turn on hardware acceleration"
                .to_string()
        })
}

/// What WebGL2 is and has, logged: DXT decoded on the CPU where S3TC is missing (or hidden by
/// `s3tc=off`, which the page's script must have done), no immediate mode, no flipped targets.
fn webgl2_extensions(
    gl: &Gl,
    contract: &PageContract,
) -> Result<(ContextInfo, GlExtensions), String> {
    let info = webgl2_info(gl);
    log::info!("WebGL2 on {} ({})", info.renderer, info.vendor);
    let s3tc = info.extensions.iter().any(|e| e == WEBGL_S3TC_EXTENSION);
    if s3tc && !contract.s3tc {
        return Err(format!(
            "s3tc=off: the page's script did not hide {WEBGL_S3TC_EXTENSION} (index.html)"
        ));
    }
    if !s3tc {
        log::info!("no {WEBGL_S3TC_EXTENSION}: the DXT textures are decoded on the CPU");
    }
    let extensions = GlExtensions {
        renderer: info.renderer.clone(),
        flip_y: None,
        legacy: Err(NO_IMMEDIATE_MODE.into()),
    };
    Ok((info, extensions))
}

/// Fetches the files of `scene` (its [`SceneDescriptor::asset_files`]) the page does not hold yet,
/// for the scenes' loaders ([`crate::files::read`]): at start the first scene's only, the others'
/// when Enter or a drop opens them. Logs what it fetched.
pub(super) async fn fetch_assets(scene: &'static SceneDescriptor) -> Result<(), String> {
    let window = web_sys::window().ok_or("no window")?;
    let path = |name: &str| Path::new("assets").join(name);
    let names: Vec<&str> = (scene.asset_files.iter().copied())
        .filter(|name| !crate::files::is_file(&path(name)))
        .collect();
    if names.is_empty() {
        return Ok(());
    }
    // Every request is sent before the first is awaited: the files come in side by side.
    let requests: Vec<_> = names
        .iter()
        .map(|name| window.fetch_with_str(&format!("assets/{name}")))
        .collect();
    let mut bytes = 0;
    for (name, request) in names.iter().zip(requests) {
        let body = body(&format!("assets/{name}"), request).await?;
        bytes += body.len();
        crate::files::provide(&path(name), body);
    }
    log::info!(
        "scene {}: fetched {} ({bytes} bytes)",
        scene.name,
        names.join(", ")
    );
    Ok(())
}

/// The bytes `request` (a `fetch` of `url`) answers with.
async fn body(url: &str, request: js_sys::Promise) -> Result<Vec<u8>, String> {
    let failed = |why: &str| format!("{url}: {why}");
    let response = wasm_bindgen_futures::JsFuture::from(request)
        .await
        .map_err(|_| failed("cannot be fetched (serve the folder over HTTP)"))?;
    let response: web_sys::Response = response.dyn_into().map_err(|_| failed("no response"))?;
    if !response.ok() {
        return Err(failed(&format!("HTTP {}", response.status())));
    }
    let buffer = response.array_buffer().map_err(|_| failed("no body"))?;
    let buffer = wasm_bindgen_futures::JsFuture::from(buffer)
        .await
        .map_err(|_| failed("its body cannot be read"))?;
    Ok(js_sys::Uint8Array::new(&buffer).to_vec())
}

/// What `requestAnimationFrame` calls.
type FrameCallback = Closure<dyn FnMut()>;

/// A frame per animation frame; after `frames=N`, the last one stays.
fn animate(page: Rc<RefCell<Page>>) {
    let callback: Rc<RefCell<Option<FrameCallback>>> = Rc::new(RefCell::new(None));
    let again = callback.clone();
    let shared = page.clone();
    *callback.borrow_mut() = Some(Closure::new(move || {
        let Ok(mut page) = page.try_borrow_mut() else {
            // An input handler holds the page (it cannot, one thread running one event at a
            // time; but a frame skipped is better than a panic).
            if let Some(callback) = again.borrow().as_ref() {
                request_animation_frame(callback);
            }
            return;
        };
        page.frame();
        page.honour(&shared);
        set_frames_drawn(&mut page);
        if page.frames_left != Some(0) {
            if let Some(callback) = again.borrow().as_ref() {
                request_animation_frame(callback);
            }
        }
    }));
    let first = callback.borrow();
    if let Some(callback) = first.as_ref() {
        request_animation_frame(callback);
    }
}

fn request_animation_frame(callback: &Closure<dyn FnMut()>) {
    let Some(window) = web_sys::window() else {
        return;
    };
    let callback = callback.as_ref().unchecked_ref();
    // `frames=N` (time frozen) draws on a timer: a headless browser may hold animation frames
    // back, and a test must get its N frames.
    if FROZEN.with(std::cell::Cell::get) {
        // The timer's period is the frozen step each frame draws (the input tests predict by it).
        let period_ms = (FROZEN_STEP_S * 1000.0).round() as i32;
        let _ = window.set_timeout_with_callback_and_timeout_and_arguments_0(callback, period_ms);
    } else {
        let _ = window.request_animation_frame(callback);
    }
}

/// How many frame times the page keeps for its median (10 s at 60 frames a second; web/bench.py
/// times 100).
const FRAME_MS_KEPT: usize = 600;

thread_local! {
    /// Whether the page draws `frames=N` (see [`request_animation_frame`]).
    static FROZEN: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// `data-frames` on the canvas: how many frames are drawn (the tests wait for it); with the
/// figures BENCHMARKS.md gives: `data-first-frame-ms`, when the first frame was drawn since the
/// page's navigation began, and `data-frame-ms`, the median frame time so far; and `data-camera`
/// and `data-states` ([`Page::states`]).
fn set_frames_drawn(page: &mut Page) {
    let Some(canvas) = element("canvas") else {
        return;
    };
    let drawn = page.host.frames_drawn();
    let _ = canvas.set_attribute("data-frames", &drawn.to_string());
    if drawn == 1 {
        let now = web_sys::window()
            .and_then(|w| w.performance())
            .map_or(f64::NAN, |p| p.now());
        let _ = canvas.set_attribute("data-first-frame-ms", &format!("{now:.0}"));
    }
    if !page.frame_ms.is_empty() {
        let (_, median) = min_median(&page.frame_ms);
        let _ = canvas.set_attribute("data-frame-ms", &format!("{median:.2}"));
    }
    // The camera the frame was drawn with, and the host's state, for the input tests (`frames=N`
    // only).
    if page.frames_left.is_none() {
        return;
    }
    let _ = canvas.set_attribute("data-camera", &page.host.camera_line());
    let state = page.host.state_line();
    if page.states.last() != Some(&state) {
        page.states.push(state);
        let _ = canvas.set_attribute("data-states", &page.states.join("\n"));
    }
}
