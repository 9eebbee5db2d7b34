//! The page's input: the DOM's key, mouse, wheel and drop events, translated into the host's events
//! (key names and wheel deltas by [`crate::frontends::page_input`]); what the host asks back is done
//! after each ([`Page::honour`]).

use std::cell::RefCell;
use std::rc::Rc;

use glam::Vec2;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{DragEvent, HtmlCanvasElement, KeyboardEvent, MouseEvent, WheelEvent};

use super::{clear_error, show_error, Page};
use crate::frontends::events::Event;
use crate::frontends::keys::Key;
use crate::frontends::page_input;

/// Where a mouse event is, in canvas pixels (x right, y down).
fn at(event: &MouseEvent) -> Vec2 {
    Vec2::new(event.offset_x() as f32, event.offset_y() as f32)
}

/// Listens to `kind` on `target`: `handle` gets the page and the event, then the page does what the
/// host asked.
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
            if let Ok(mut shown) = page.try_borrow_mut() {
                handle(&mut shown, event);
                shown.honour(&page);
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

/// The host's key event for a DOM key event, if the key is one the lists name.
fn key_event(event: &KeyboardEvent, pressed: bool) -> Option<(Key, Event)> {
    let key = page_input::key(&event.key())?;
    let event = Event::Key {
        key,
        pressed,
        repeat: event.repeat(),
        ctrl: event.ctrl_key(),
    };
    Some((key, event))
}

/// The keys, for the host.
fn listen_to_keys(window: &web_sys::Window, page: &Rc<RefCell<Page>>) -> Result<(), String> {
    on(window, "keydown", page, |page, event: KeyboardEvent| {
        let translated = key_event(&event, true);
        let arrow = matches!(translated, Some((Key::Arrow(_), _)));
        // The last message goes with a new press; what this key brings (an error, a notice)
        // replaces it.
        if !arrow && !event.repeat() {
            clear_error();
        }
        let Some((key, translated)) = translated else {
            return;
        };
        // The page must not scroll or reload on the keys the scenes use.
        if arrow || page.host.host_key(key).is_some() {
            event.prevent_default();
        }
        page.event(translated);
    })?;
    on(window, "keyup", page, |page, event: KeyboardEvent| {
        if let Some((_, translated)) = key_event(&event, false) {
            page.event(translated);
        }
    })
}

/// The mouse and the wheel, each where it happened.
fn listen_to_mouse(canvas: &HtmlCanvasElement, page: &Rc<RefCell<Page>>) -> Result<(), String> {
    on(canvas, "mousedown", page, |page, event: MouseEvent| {
        page.event(Event::PointerMoved(at(&event)));
        page.event(Event::Button { pressed: true });
    })?;
    on(canvas, "mouseup", page, |page, event: MouseEvent| {
        page.event(Event::PointerMoved(at(&event)));
        page.event(Event::Button { pressed: false });
    })?;
    on(canvas, "mousemove", page, |page, event: MouseEvent| {
        page.event(Event::PointerMoved(at(&event)));
    })?;
    on(canvas, "mouseleave", page, |page, _: MouseEvent| {
        page.event(Event::PointerLeft);
    })?;
    on(canvas, "wheel", page, |page, event: WheelEvent| {
        event.prevent_default();
        let notches =
            page_input::wheel_notches(event.delta_x(), event.delta_y(), event.delta_mode());
        page.event(Event::PointerMoved(at(&event)));
        page.event(Event::Wheel(notches));
    })
}

/// Files dropped on the canvas: read, kept where the loaders find them, and given to the host.
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
            let paths = Page::keep_dropped(read);
            let mut shown = page.borrow_mut();
            clear_error();
            shown.event(Event::DroppedFiles(paths));
            shown.honour(&page);
        });
    })
}
