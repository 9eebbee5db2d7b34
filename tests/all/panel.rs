//! The panel headless: drawn over the frame without touching a pixel outside its
//! rectangle, listing exactly the scene's keys, and changing the scene only as its keys and sliders
//! say. Clicks are real pointer events given to egui (the same input the window's egui-winit glue
//! produces), aimed at where the panel drew each widget.

use tutorial13::frontends::events::Event;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::keys::{panel_key_rows, FrontEnd};
use tutorial13::frontends::panel::PanelWidget;
use tutorial13::scenes::{ControlState, ControlValue, SceneDescriptor, SetTo, SCENES};

use crate::common::{self, frame};

fn renderer_for(scene: &'static SceneDescriptor) -> HeadlessRenderer {
    common::renderer(&HeadlessOptions {
        descriptor: scene,
        ..Default::default()
    })
}

/// A left click at the centre of `widget`: the pointer moves there in one frame, the button goes
/// down in the next and up in the one after, as a hand's click spans frames.
fn click(renderer: &mut HeadlessRenderer, widget: PanelWidget) {
    let rect = panel_rect_of(renderer, &widget);
    click_at(renderer, rect.center());
}

fn click_at(renderer: &mut HeadlessRenderer, pos: egui::Pos2) {
    let at = glam::Vec2::new(pos.x, pos.y);
    renderer.event(Event::PointerMoved(at)).unwrap();
    renderer.render().unwrap();
    for pressed in [true, false] {
        renderer.event(Event::Button { pressed }).unwrap();
        renderer.render().unwrap();
    }
}

/// The scene's sliders, in its table's order.
fn sliders(renderer: &HeadlessRenderer) -> Vec<ControlState> {
    let controls = renderer.host.scene.controls().into_iter();
    controls
        .filter(|c| matches!(c.value, ControlValue::Slider { .. }))
        .collect()
}

/// A slider's value and start.
fn value_and_start(slider: &ControlState) -> (f32, f32) {
    match slider.value {
        ControlValue::Slider { value, start, .. } => (value, start),
        _ => panic!("{} is no slider", slider.label),
    }
}

fn panel_rect_of(renderer: &HeadlessRenderer, widget: &PanelWidget) -> egui::Rect {
    let panel = renderer.host.panel().expect("the panel is shown");
    panel
        .widget_rect(widget)
        .unwrap_or_else(|| panic!("the panel shows no {widget:?}"))
}

// Fails if the panel draws nothing, or changes any pixel outside its rectangle (the scene's frame
// must stay the scene's, bit for bit), or raises a GL error, in any scene; or if the copy kept of
// an unchanged panel differs from painting it, in any of the frames that copy it, with the copy
// stored in the frame's byte order or in a window's.
#[test]
fn the_panel_changes_only_its_own_rectangle() {
    for scene in SCENES {
        let mut renderer = renderer_for(scene);
        let plain = frame(&mut renderer);
        renderer.host.show_panel().unwrap();
        let with_panel = frame(&mut renderer);
        let rect = renderer.host.panel().unwrap().rect().expect("laid out");
        assert!(
            rect.width() > 200.0 && rect.height() >= 767.0,
            "{scene}: {rect:?}"
        );
        let (mut inside_changed, mut outside_changed) = (0, 0);
        for (x, y, p) in with_panel.enumerate_pixels() {
            let inside = rect.contains(egui::pos2(x as f32 + 0.5, y as f32 + 0.5));
            let changed = plain.get_pixel(x, y) != p;
            match (inside, changed) {
                (true, true) => inside_changed += 1,
                (false, true) => outside_changed += 1,
                _ => {}
            }
        }
        assert_eq!(
            outside_changed, 0,
            "{scene}: pixels outside the panel changed"
        );
        assert!(
            inside_changed > 10_000,
            "{scene}: the panel drew {inside_changed} pixels"
        );
        // The next frames copy the panel from its cache (laid out again only when something
        // changed): the same pixels as painting it again. Then again from a cache stored in a
        // window's byte order, as the window keeps it (a cache stored unflipped would show here).
        for window_order in [false, true] {
            if window_order {
                renderer
                    .host
                    .panel_mut()
                    .unwrap()
                    .store_cache_like_a_window();
            }
            for n in 2..4 {
                assert!(
                    frame(&mut renderer) == with_panel,
                    "{scene}: frame {n} differs (cache in the window's order: {window_order})"
                );
            }
        }
        renderer.host.panel_mut().unwrap().paint_every_frame = true;
        assert!(
            frame(&mut renderer) == with_panel,
            "{scene}: painted again, it differs"
        );
        // Painting the panel leaves no state that changes the next frame of the scene.
        renderer.host.set_panel_shown(false);
        assert!(
            frame(&mut renderer) == plain,
            "{scene}: the frame after the panel differs"
        );
    }
}

// Fails if the panel's list of scene keys is not the scene's bindings (same keys, same words, same
// order), if a switch the scene shows on the panel has no key, or if pressing that key does not
// change the state the panel shows (the panel would show a state the key does not follow).
#[test]
fn the_panel_lists_the_scene_keys_and_their_switches_follow_them() {
    for scene in SCENES {
        let rows: Vec<(char, &str)> = panel_key_rows(scene, FrontEnd::Window)
            .into_iter()
            .filter_map(|r| r.scene_key.map(|k| (k, r.help)))
            .collect();
        let bindings: Vec<(char, &str)> = scene.keys.iter().map(|k| (k.key, k.help)).collect();
        assert_eq!(rows, bindings, "{scene}");

        let mut renderer = renderer_for(scene);
        let switches: Vec<ControlState> = renderer
            .host
            .scene
            .controls()
            .into_iter()
            .filter(|c| {
                matches!(
                    c.value,
                    ControlValue::Toggle(_) | ControlValue::Choice { .. }
                )
            })
            .collect();
        assert!(!switches.is_empty(), "{scene} shows no switch");
        for switch in switches {
            let key = switch.key.expect("a switch has a key");
            assert!(
                scene.keys.iter().any(|k| k.key == key),
                "{scene}: switch {key} has no key"
            );
            if let ControlValue::Choice { current, choices } = &switch.value {
                assert!(
                    choices.contains(current),
                    "{scene}: {current} not in {choices:?}"
                );
                if choices.len() == 1 {
                    continue; // nothing to step to in this context
                }
            }
            assert!(renderer.host.scene.key(key).unwrap());
            // One that does nothing in this state says why (the panel greys it).
            let now = &renderer.host.scene.controls()[switch.index];
            if now.inert.is_some() && now.value == switch.value {
                renderer.render_frames(1).unwrap();
                continue;
            }
            assert_ne!(
                now.value, switch.value,
                "{scene}: key {key} changed nothing"
            );
            renderer.render_frames(1).unwrap();
        }
    }
}

// Fails if clicking a switch's checkbox does something else than pressing its key: the status and
// the frame after the click must equal those of a renderer whose key was pressed (L: the TBN lines).
#[test]
fn clicking_a_checkbox_does_what_its_key_does() {
    let scene = tutorial13::scenes::default_scene();
    let mut pressed = renderer_for(scene);
    pressed.host.scene.key('L').unwrap();
    let expected = frame(&mut pressed);

    let mut clicked = renderer_for(scene);
    let start = frame(&mut clicked);
    clicked.host.show_panel().unwrap();
    frame(&mut clicked);
    click(&mut clicked, PanelWidget::Key('L'));
    assert_eq!(clicked.host.scene.status(), pressed.host.scene.status());
    clicked.host.set_panel_shown(false);
    let after = frame(&mut clicked);
    assert!(after == expected, "the click did not draw the key's frame");
    assert!(after != start, "the lines did not appear");
}

// Fails if a choice on the panel does not set the chosen value (V: the colour view "normal01"), or if the scene's drawing programs, which the panel lists, name another program than
// the one drawing (the tutorial's until an experiment, then NormalMappingDebug with its files).
#[test]
fn a_choice_sets_its_value_and_the_panel_names_the_program() {
    let mut renderer = renderer_for(tutorial13::scenes::default_scene());
    let program = |r: &HeadlessRenderer| r.host.scene.drawing_programs()[0].name.clone();
    assert!(
        program(&renderer).starts_with("NormalMapping "),
        "{}",
        program(&renderer)
    );
    renderer.host.show_panel().unwrap();
    frame(&mut renderer);
    // The combo box opens on a click; its choices are then listed below it, one row each.
    let combo = panel_rect_of(&renderer, &PanelWidget::Key('V'));
    let mut chosen = false;
    for dy in (8..240).step_by(8) {
        click(&mut renderer, PanelWidget::Key('V'));
        let below = combo.center_bottom() + egui::vec2(0.0, dy as f32);
        click_at(&mut renderer, below);
        if renderer.host.scene.status().contains("view normal01") {
            chosen = true;
            break;
        }
    }
    assert!(
        chosen,
        "no click chose normal01: {}",
        renderer.host.scene.status()
    );
    let drawing = &renderer.host.scene.drawing_programs()[0];
    assert!(
        drawing.name.starts_with("NormalMappingDebug"),
        "{}",
        drawing.name
    );
    assert!(drawing
        .files()
        .iter()
        .any(|f| f.ends_with("NormalMappingDebug.fragmentshader")));
}

// Fails if a light slider does not move the light (the frame must change), if the panel does not
// then offer the tutorial's values, or if that button does not bring back the first frame bit for
// bit (and the tutorial's own program with it).
#[test]
fn a_slider_moves_the_light_and_the_tutorials_values_bring_the_first_frame_back() {
    for scene in SCENES {
        let mut renderer = renderer_for(scene);
        let first = frame(&mut renderer);
        let first_programs = renderer.host.scene.drawing_programs();
        renderer.host.show_panel().unwrap();
        frame(&mut renderer);
        let first_slider = sliders(&renderer)[0].clone();
        let (name, index) = (first_slider.label, first_slider.index);
        let slider = panel_rect_of(&renderer, &PanelWidget::Slider(index));
        // Near the left end of the rail (the widget's first 100 points).
        click_at(&mut renderer, slider.left_center() + egui::vec2(12.0, 0.0));
        let (value, start) = value_and_start(&renderer.host.scene.controls()[index]);
        assert_ne!(value, start, "{scene}: the {name} slider did not move");
        renderer.host.set_panel_shown(false);
        assert!(
            frame(&mut renderer) != first,
            "{scene}: moving {name} changed nothing"
        );
        renderer.host.set_panel_shown(true);
        frame(&mut renderer);
        click(&mut renderer, PanelWidget::StartValues);
        for slider in sliders(&renderer) {
            let (value, start) = value_and_start(&slider);
            assert_eq!(value, start, "{scene}: {}", slider.label);
        }
        renderer.host.set_panel_shown(false);
        assert!(
            frame(&mut renderer) == first,
            "{scene}: not the first frame again"
        );
        assert_eq!(
            renderer.host.scene.drawing_programs(),
            first_programs,
            "{scene}"
        );
    }
}

// Fails if the cylinder's light power, normal strength or line length sliders change nothing, or
// if moving one away does not switch to the debugging program (the tutorial's shader has them as
// constants) and say so in the scene's drawing programs, which the panel lists.
#[test]
fn the_cylinders_sliders_each_change_the_frame() {
    let options = HeadlessOptions::default();
    let mut renderer = common::renderer(&options);
    renderer.host.scene.key('L').unwrap();
    let first = frame(&mut renderer);
    for (name, value) in [
        ("light power", 80.0),
        ("normal strength", 0.0),
        ("TBN line length", 0.3),
    ] {
        let index = renderer.host.scene.control_index(name).unwrap();
        renderer
            .host
            .scene
            .set_control(index, SetTo::Slider(value))
            .unwrap();
        let moved = frame(&mut renderer);
        assert!(common::differing_pixels(&moved, &first) > 1000, "{name}");
        let names: Vec<String> = renderer
            .host
            .scene
            .drawing_programs()
            .into_iter()
            .map(|p| p.name)
            .collect();
        let debug = names[0].starts_with("NormalMappingDebug");
        assert_eq!(debug, name != "TBN line length", "{name}: {names:?}");
        let (_, start) = value_and_start(&renderer.host.scene.controls()[index]);
        renderer
            .host
            .scene
            .set_control(index, SetTo::Slider(start))
            .unwrap();
        assert!(frame(&mut renderer) == first, "{name}: back at {start}");
    }
}

/// A scene with `args` on its command line (the crate's own assets), as the binary builds it.
fn renderer_with_flags(scene: &'static SceneDescriptor, args: &[String]) -> HeadlessRenderer {
    let command = tutorial13::scenes::command_line(clap::Command::new("t"));
    let argv = std::iter::once("t".to_string()).chain(args.iter().cloned());
    let matches = command.try_get_matches_from(argv).unwrap();
    let options = tutorial13::scenes::scene_options(&matches, scene, Default::default())
        .unwrap_or_else(|e| panic!("{scene} {args:?}: {e}"));
    common::renderer(&HeadlessOptions {
        descriptor: scene,
        scene: options,
        ..Default::default()
    })
}

/// The flags slider `label` of `scene` needs to apply at all, and the flag that starts it at
/// `value` (`light` is where the scene's light starts, for the sliders of one of its axes).
fn flags_of_slider(scene: &str, label: &str, value: f32, light: [f32; 3]) -> [Vec<String>; 2] {
    let light_with = |axis: usize| {
        let mut at = light;
        at[axis] = value;
        vec!["--light".into(), format!("{},{},{}", at[0], at[1], at[2])]
    };
    let (needs, flag): (&[&str], Vec<String>) = match (scene, label) {
        (_, "light x") => (&[], light_with(0)),
        (_, "light y") => (&[], light_with(1)),
        (_, "light z") | ("sprite", "light height") => (&[], light_with(2)),
        (_, "light power") => (&[], vec!["--light-power".into(), value.to_string()]),
        ("cylinder", "normal strength") => {
            (&[], vec!["--normal-strength".into(), value.to_string()])
        }
        ("cylinder", "TBN line length") => (
            &["--debug-lines"],
            vec!["--line-length".into(), value.to_string()],
        ),
        ("cylinder", "compare split") => (
            &["--compare", "tutorial,mikktspace"],
            vec!["--split".into(), value.to_string()],
        ),
        _ => panic!("{scene}: no flag known for the {label} slider"),
    };
    [needs.iter().map(|s| s.to_string()).collect(), flag]
}

// Fails if any slider of any scene, moved on the panel, does not give bit for bit the frame of the
// command-line flag it stands for (--light with the other axes where they were, --light-power,
// --normal-strength, --line-length, --split), or if the scene started with that flag does not show
// the slider at that value; or if the moved slider left the frame as it was.
#[test]
fn each_slider_gives_the_frame_of_its_flag() {
    let mut checked = Vec::new();
    for scene in SCENES {
        let labels: Vec<&str> = sliders(&renderer_for(scene))
            .iter()
            .map(|s| s.label)
            .collect();
        for label in labels {
            // A value 30 % along the slider's range (70 % where it starts there), as the command
            // line writes it.
            let probe = renderer_for(scene);
            let slider = sliders(&probe)
                .into_iter()
                .find(|s| s.label == label)
                .unwrap();
            let ControlValue::Slider {
                range, value: now, ..
            } = slider.value
            else {
                unreachable!()
            };
            let along = |f: f32| -> f32 {
                let v = range.0 + f * (range.1 - range.0);
                format!("{v:.3}").parse().unwrap()
            };
            let value = if along(0.3) == now {
                along(0.7)
            } else {
                along(0.3)
            };
            let light_axis = |axis: &str| {
                let at = sliders(&probe).into_iter().find(|s| s.label == axis);
                at.map_or(0.0, |s| value_and_start(&s).0)
            };
            let mut light = ["light x", "light y", "light z"].map(light_axis);
            if scene.name == "sprite" {
                let sprite = probe.scene_ref::<tutorial13::scenes::sprite::Sprite>();
                light = sprite.light.to_array();
            }
            drop(probe);
            let [needs, flag] = flags_of_slider(scene.name, label, value, light);

            let mut moved = renderer_with_flags(scene, &needs);
            let before = frame(&mut moved);
            let index = moved.host.scene.control_index(label).unwrap();
            assert_eq!(
                moved.host.scene.controls()[index].inert,
                None,
                "{scene}: {label}"
            );
            moved
                .host
                .scene
                .set_control(index, SetTo::Slider(value))
                .unwrap();
            let moved_frame = frame(&mut moved);
            drop(moved);
            assert!(
                moved_frame != before,
                "{scene}: {label} at {value} changed nothing"
            );

            let mut args = needs.clone();
            args.extend(flag.iter().cloned());
            let mut flagged = renderer_with_flags(scene, &args);
            let shown = value_and_start(&flagged.host.scene.controls()[index]).0;
            assert_eq!(shown, value, "{scene} {args:?}: the {label} slider");
            assert!(
                frame(&mut flagged) == moved_frame,
                "{scene}: {label} at {value} is not the frame of {args:?}"
            );
            checked.push(format!("{scene} {label}"));
        }
    }
    println!("{checked:?}");
    assert_eq!(checked.len(), 16, "{checked:?}");
}

// Fails if the panel's first frame after a change of scene is laid out with the last scene's sizes
// (egui takes a grid's columns from the frame before and its rows' stripes from the one before
// that): from each scene, switching through the others in turn, each scene's first frame with the
// panel must equal its first frame with the panel on a fresh renderer, bit for bit. Laid out
// once at the switch, the sprite after the cylinder differed in 4,352 pixels; twice, in 1,272.
#[test]
fn the_first_panel_after_a_change_of_scene_is_the_new_scenes() {
    let alone: Vec<_> = SCENES
        .iter()
        .map(|&b| {
            let mut renderer = renderer_for(b);
            renderer.host.show_panel().unwrap();
            frame(&mut renderer)
        })
        .collect();
    for &a in &SCENES {
        let mut renderer = renderer_for(a);
        renderer.host.show_panel().unwrap();
        frame(&mut renderer);
        for (&b, alone) in SCENES.iter().zip(&alone).filter(|(&b, _)| b != a) {
            let before = renderer.host.descriptor();
            renderer.host.switch_scene(b).unwrap();
            let after = frame(&mut renderer);
            let differ = after
                .pixels()
                .zip(alone.pixels())
                .filter(|(x, y)| x != y)
                .count();
            assert_eq!(differ, 0, "{b} after {before}: {differ} pixels differ");
        }
    }
}
