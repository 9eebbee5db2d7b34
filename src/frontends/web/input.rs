//! The page's input: the DOM's key, mouse, wheel and drop events, turned into what the window's
//! front end gives the host and the panel.

use std::cell::RefCell;
use std::rc::Rc;

use glam::Vec2;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{DragEvent, HtmlCanvasElement, KeyboardEvent, MouseEvent, WheelEvent};

use super::{mouse_mode, show_error, Page};
use crate::frontends::host::Arrow;
use crate::frontends::{FrontEnd, HostAction, HostKey};
use crate::scenes::{MouseMode, SceneOptions};

/// An arrow key by its DOM `key`.
pub fn arrow(key: &str) -> Option<Arrow> {
    match key {
        "ArrowUp" => Some(Arrow::Up),
        "ArrowDown" => Some(Arrow::Down),
        "ArrowLeft" => Some(Arrow::Left),
        "ArrowRight" => Some(Arrow::Right),
        _ => None,
    }
}

/// A scene key by its DOM `key`: a letter (upper-case, as the scenes' lists give them) or a digit.
pub fn key_char(key: &str) -> Option<char> {
    let mut chars = key.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) if c.is_ascii_alphanumeric() => Some(c.to_ascii_uppercase()),
        _ => None,
    }
}

/// What a DOM `key` does on the page, if it is one of the front ends' own keys the page has
/// ([`crate::frontends::HOST_KEYS`]).
pub fn host_action(key: &str) -> Option<HostAction> {
    let name = match key {
        "Escape" => "Esc",
        "r" => "R",
        "p" => "P",
        other => other,
    };
    HostKey::find(name, FrontEnd::Page)
}

/// Where a mouse event is, in canvas pixels (x right, y down).
fn at(event: &MouseEvent) -> Vec2 {
    Vec2::new(event.offset_x() as f32, event.offset_y() as f32)
}

fn on<E: JsCast + 'static>(
    target: &web_sys::EventTarget,
    kind: &str,
    page: &Rc<RefCell<Page>>,
    mut handle: impl FnMut(&mut Page, E) + 'static,
) -> Result<(), String> {
    let page = page.clone();
    let closure = Closure::<dyn FnMut(web_sys::Event)>::new(move |event: web_sys::Event| {
        if let Ok(event) = event.dyn_into::<E>() {
            // A handler never runs inside a frame (one thread, one event at a time).
            if let Ok(mut page) = page.try_borrow_mut() {
                handle(&mut page, event);
            }
        }
    });
    target
        .add_event_listener_with_callback(kind, closure.as_ref().unchecked_ref())
        .map_err(|_| format!("cannot listen to {kind}"))?;
    // The page lives as long as the tab: the listener is never removed.
    closure.forget();
    Ok(())
}

/// Listens to the window's keys and the canvas's mouse, wheel and drops.
pub fn listen(
    window: &web_sys::Window,
    canvas: &HtmlCanvasElement,
    page: &Rc<RefCell<Page>>,
) -> Result<(), String> {
    listen_to_keys(window, page)?;
    listen_to_mouse(canvas, page)?;
    listen_to_drops(canvas, page)
}

/// The keys: arrows to the host as held, the page's own keys by the table, the rest to the scene.
fn listen_to_keys(window: &web_sys::Window, page: &Rc<RefCell<Page>>) -> Result<(), String> {
    let switching = page.clone();
    on(
        window,
        "keydown",
        page,
        move |page, event: KeyboardEvent| {
            let key = event.key();
            let action = host_action(&key);
            // The page must not scroll or reload on the keys the scenes use.
            if arrow(&key).is_some() || action.is_some() {
                event.prevent_default();
            }
            if action == Some(HostAction::NextScene) && !event.repeat() {
                // The next scene once its files are in (fetched the first time it opens).
                let from = page.host.descriptor();
                let next = crate::scenes::next(from);
                let page = switching.clone();
                wasm_bindgen_futures::spawn_local(async move {
                    match super::fetch_assets(next).await {
                        Ok(()) => page.borrow_mut().switch_scene(from, next),
                        Err(e) => show_error(&e),
                    }
                });
            } else if !event.repeat() || arrow(&key).is_some() {
                page.key(&key, true);
            }
        },
    )?;
    on(window, "keyup", page, |page, event: KeyboardEvent| {
        page.key(&event.key(), false);
    })
}

/// The mouse and the wheel: the panel's where the pointer is over it, else a drag looks around (or
/// the scene's free cursor follows) and the wheel goes to the scene.
fn listen_to_mouse(canvas: &HtmlCanvasElement, page: &Rc<RefCell<Page>>) -> Result<(), String> {
    let button = |pos: Vec2, pressed: bool| egui::Event::PointerButton {
        pos: egui::pos2(pos.x, pos.y),
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::default(),
    };
    on(canvas, "mousedown", page, move |page, event: MouseEvent| {
        let pos = at(&event);
        if page.host.over_panel(pos) {
            page.host.panel_event(button(pos, true));
            return;
        }
        match mouse_mode(page) {
            MouseMode::Look => page.dragging = Some(pos),
            MouseMode::Cursor => page.host.click(),
        }
    })?;
    on(canvas, "mouseup", page, move |page, event: MouseEvent| {
        page.dragging = None;
        page.host.panel_event(button(at(&event), false));
    })?;
    on(canvas, "mousemove", page, |page, event: MouseEvent| {
        let pos = at(&event);
        (page.host).panel_event(egui::Event::PointerMoved(egui::pos2(pos.x, pos.y)));
        if let Some(from) = page.dragging {
            page.dragging = Some(pos);
            let moved = pos - from;
            page.host.look((f64::from(moved.x), f64::from(moved.y)));
        }
        page.host.cursor = (!page.host.over_panel(pos)).then_some(pos);
    })?;
    on(canvas, "mouseleave", page, |page, _: MouseEvent| {
        page.dragging = None;
        page.host.cursor = None;
        page.host.panel_event(egui::Event::PointerGone);
    })?;
    on(canvas, "wheel", page, |page, event: WheelEvent| {
        event.prevent_default();
        let pos = Vec2::new(event.offset_x() as f32, event.offset_y() as f32);
        if page.host.over_panel(pos) {
            page.host.panel_event(egui::Event::MouseWheel {
                unit: egui::MouseWheelUnit::Point,
                delta: egui::vec2(-event.delta_x() as f32, -event.delta_y() as f32),
                modifiers: egui::Modifiers::default(),
                phase: egui::TouchPhase::Move,
                source: egui::MouseWheelSource::Unknown,
            });
        } else {
            // A notch is about 100 pixels of DOM delta; positive away from the user, as winit's.
            page.host.scroll((-event.delta_y() / 100.0) as f32);
        }
    })
}

/// Files dropped on the canvas: read, kept where the loaders find them, and the model among them
/// opened once the scene that opens it has its files.
fn listen_to_drops(canvas: &HtmlCanvasElement, page: &Rc<RefCell<Page>>) -> Result<(), String> {
    on(canvas, "dragover", page, |_, event: DragEvent| {
        event.prevent_default();
    })?;
    let dropped = page.clone();
    on(canvas, "drop", page, move |_, event: DragEvent| {
        event.prevent_default();
        let Some(list) = event.data_transfer().and_then(|d| d.files()) else {
            return;
        };
        let files: Vec<web_sys::File> = (0..list.length()).filter_map(|i| list.get(i)).collect();
        let page = dropped.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let mut read = Vec::new();
            for file in files {
                let name = file.name();
                match wasm_bindgen_futures::JsFuture::from(file.array_buffer()).await {
                    Ok(buffer) => read.push((name, js_sys::Uint8Array::new(&buffer).to_vec())),
                    Err(_) => return show_error(&format!("{name}: cannot be read")),
                }
            }
            let Some(model) = Page::keep_dropped(read) else {
                return;
            };
            // The scene that opens it needs its own files too (the cylinder's maps under a model
            // without its own), which a page started on another scene has not fetched yet.
            let opens = crate::scenes::open_file(&model, &mut SceneOptions::default());
            if let Ok(scene) = opens {
                if let Err(e) = super::fetch_assets(scene).await {
                    return show_error(&e);
                }
            }
            page.borrow_mut().open_file(&model);
        });
    })
}
