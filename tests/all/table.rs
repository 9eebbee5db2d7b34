//! The scenes' tables of controls: the key list is the table's, the panel sets a choice directly
//! (building only what that value needs), and a control that does nothing in the scene's state
//! says why instead of being shown as on.

use tutorial13::frontends::events::Event;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::panel::PanelWidget;
use tutorial13::gl::Profile;
use tutorial13::scenes::cylinder::{self, Cylinder};
use tutorial13::scenes::{ControlValue, SceneControls, SceneOptions, SetTo, SCENES};
use tutorial13::tangent_source::TangentSource;

use crate::common::*;

// Fails if a scene's key list (`--help`, the window, docs/keys.md, the panel's rows) is not the keys
// of its table of controls, in the table's order with the table's words, or if a key of the list
// is not the key of its control.
#[test]
fn the_key_list_is_the_tables() {
    for scene in SCENES {
        let mut renderer = renderer(&HeadlessOptions {
            descriptor: scene,
            ..Default::default()
        });
        let controls = renderer.host.scene.controls();
        let keyed: Vec<(char, &str)> = controls
            .iter()
            .filter_map(|c| Some((c.key?, c.help)))
            .collect();
        let listed: Vec<(char, &str)> = scene.keys.iter().map(|k| (k.key, k.help)).collect();
        assert_eq!(listed, keyed, "{scene}");
        let markdown = crate::docs::keys_markdown();
        for (key, help) in keyed {
            assert!(
                markdown.contains(&format!("| {key} | {help} |")),
                "{scene}: {key}"
            );
            // The key reaches its control: a switch's state follows it.
            let index = controls.iter().position(|c| c.key == Some(key)).unwrap();
            let before = renderer.host.scene.controls()[index].value.clone();
            assert!(renderer.host.scene.key(key.to_ascii_lowercase()).unwrap());
            let after = renderer.host.scene.controls()[index].value.clone();
            if let ControlValue::Toggle(on) = before {
                assert_eq!(after, ControlValue::Toggle(!on), "{scene}: {key}");
            }
        }
    }
}

// Fails if a scene's status line (the log's) is not its table read now: every control with a state
// that applies, as "label value" in the table's order, then only what the table does not hold; or if
// it names a control that does nothing (the cylinder's per-pixel frame leaves out the colour view, the
// lines and the shader's experiments), or if a switch's new value does not show in it.
#[test]
fn the_status_line_is_the_tables() {
    let per_pixel = derivative_options(|_| {});
    let cases = SCENES
        .iter()
        .map(|&scene| HeadlessOptions {
            descriptor: scene,
            ..Default::default()
        })
        .chain([per_pixel]);
    for options in cases {
        let scene = options.descriptor;
        let mut renderer = renderer(&options);
        for round in 0..2 {
            let controls = renderer.host.scene.controls();
            let expected: Vec<String> = controls
                .iter()
                .filter(|c| c.inert.is_none() && c.value != ControlValue::Press)
                .map(|c| format!("{} {}", c.label, c.value.shown()))
                .collect();
            let status = renderer.host.scene.status();
            let expected = expected.join(" | ");
            assert!(
                status.starts_with(&expected),
                "{scene}:\n{status}\n{expected}"
            );
            let beyond = &status[expected.len()..];
            for c in controls.iter().filter(|c| c.inert.is_some()) {
                let named = format!("{} ", c.label);
                assert!(
                    !status.starts_with(&named) && !status.contains(&format!("| {named}")),
                    "{scene}: {} does nothing, yet: {status}",
                    c.label
                );
            }
            assert!(
                beyond.is_empty() || beyond.starts_with(" | "),
                "{scene}: {beyond}"
            );
            // Flip the first toggle that applies: the next round reads its new value.
            if round == 0 {
                let Some(toggle) = controls
                    .iter()
                    .find(|c| c.inert.is_none() && matches!(c.value, ControlValue::Toggle(_)))
                else {
                    break;
                };
                let ControlValue::Toggle(on) = toggle.value else {
                    unreachable!()
                };
                let index = toggle.index;
                renderer
                    .host
                    .scene
                    .set_control(index, SetTo::Toggle(!on))
                    .unwrap();
                let shown = format!("{} {}", toggle.label, if on { "off" } else { "on" });
                assert!(
                    renderer.host.scene.status().contains(&shown),
                    "{scene}: {shown}"
                );
            }
        }
    }
}

// Fails if choosing a tangent frame on the panel builds any other source's mesh than the chosen
// one: from the tutorial's to the per-pixel frame, MikkTSpace (a whole pass over a big model) must
// not run on the way, as it did when the panel pressed F until the value came up.
#[test]
fn choosing_a_tangent_frame_on_the_panel_builds_only_its_mesh() {
    let mut renderer = renderer(&HeadlessOptions::default());
    renderer.host.show_panel().unwrap();
    frame(&mut renderer);
    click(&mut renderer, PanelWidget::Key('F'));
    // The list is open: its third row is "derivative".
    click(&mut renderer, PanelWidget::Choice('F', 2));
    let cylinder = renderer.scene_ref::<Cylinder>();
    assert_eq!(cylinder.tangent_source(), TangentSource::Derivative);
    assert_eq!(cylinder.meshes_built(), [TangentSource::Derivative]);
    // The same through the table, from the per-pixel frame back to the tutorial's.
    let f = renderer.host.scene.control_index("tangent frame").unwrap();
    let to = SetTo::Choice("tutorial".into());
    renderer.host.scene.set_control(f, to).unwrap();
    let built = renderer.scene_ref::<Cylinder>().meshes_built().to_vec();
    assert_eq!(built, [TangentSource::Derivative, TangentSource::Tutorial]);
}

/// A left click at the centre of `widget` over three frames (move, press, release).
fn click(renderer: &mut HeadlessRenderer, widget: PanelWidget) {
    let panel = renderer.host.panel().expect("the panel is shown");
    let pos = panel
        .widget_rect(&widget)
        .unwrap_or_else(|| panic!("the panel shows no {widget:?}"))
        .center();
    let at = glam::Vec2::new(pos.x, pos.y);
    renderer.event(Event::PointerMoved(at)).unwrap();
    renderer.render_frames(1).unwrap();
    for pressed in [true, false] {
        renderer.event(Event::Button { pressed }).unwrap();
        renderer.render_frames(1).unwrap();
    }
}

fn derivative_options(set: impl FnOnce(&mut SceneOptions)) -> HeadlessOptions {
    let mut options = options(own_assets(), Profile::Core);
    options
        .scene
        .start(cylinder::TANGENTS.to(TangentSource::Derivative));
    set(&mut options.scene);
    options
}

/// The key and label of each control of the renderer's scene that does nothing now.
fn inert_controls(
    renderer: &HeadlessRenderer,
) -> impl Iterator<Item = (Option<char>, &'static str)> {
    let controls = renderer.host.scene.controls();
    controls
        .into_iter()
        .filter(|c| c.inert.is_some())
        .map(|c| (c.key, c.label))
}

// Fails if, with the per-pixel frame, a switch it ignores (V, C, S, T, Y, E, Z, L) does not say
// why it does nothing, or if one that applies says it does not; if the title or the status line
// still claims a colour view, lines or a shader experiment; or if pressing such a key changes the
// frame (it must stay the per-pixel frame, bit for bit) or is not taken as the scene's key.
#[test]
fn the_per_pixel_frame_says_which_switches_do_nothing() {
    let mut renderer = renderer(&derivative_options(|_| {}));
    let plain = frame(&mut renderer);
    let inert: Vec<char> = inert_controls(&renderer)
        .filter_map(|(key, _)| key)
        .collect();
    // M: a core context has no immediate mode; A, D: the compare view is off.
    assert_eq!(
        inert,
        ['L', 'M', 'V', 'C', 'S', 'T', 'A', 'D', 'Y', 'E', 'Z'],
        "{:?}",
        renderer.host.scene.controls()
    );
    let title = renderer.host.scene.short_status();
    assert_eq!(title, "tangents derivative");
    let status = renderer.host.scene.status();
    for claim in [
        "colour view",
        "TBN debug lines",
        "specular texture",
        "normalized TBN",
        "green down",
        "exact expansion",
        "two channels",
    ] {
        assert!(!status.contains(claim), "{claim}: {status}");
    }
    for key in ['V', 'C', 'S', 'T', 'Y', 'E', 'Z', 'L'] {
        assert!(renderer.host.scene.key(key).unwrap(), "{key}");
        assert!(frame(&mut renderer) == plain, "{key} changed the frame");
        assert_eq!(renderer.host.scene.short_status(), title, "{key}");
    }
    // The tutorial's frame: all of them apply (the title names view and lines again).
    let f = renderer.host.scene.control_index("tangent frame").unwrap();
    let to = SetTo::Choice("tutorial".into());
    renderer.host.scene.set_control(f, to).unwrap();
    // Only those that need another state: immediate mode (none in a core context) and the compare
    // view's split line (the view is off); the lines are on (L above), so their length applies.
    let inert: Vec<&str> = inert_controls(&renderer).map(|(_, label)| label).collect();
    assert_eq!(
        inert,
        [
            "lines drawn with",
            "split line left",
            "split line right",
            "compare split"
        ]
    );
    let title = renderer.host.scene.short_status();
    assert!(
        title.contains("view ") && title.contains("lines "),
        "{title}"
    );
}

// Fails if the compare view compares a colour view with the per-pixel frame (which draws none: a
// heat map of two kinds of picture) instead of saying why it does not, or refuses a like-for-like
// comparison.
#[test]
fn the_compare_view_compares_like_with_like() {
    let mut renderer = renderer(&options(own_assets(), Profile::Core));
    // MikkTSpace against the next source, the per-pixel frame, with the colour view "normal".
    let set = |r: &mut HeadlessRenderer, label, to| {
        let index = r.host.scene.control_index(label).unwrap();
        r.host.scene.set_control(index, to).unwrap();
    };
    set(
        &mut renderer,
        "tangent frame",
        SetTo::Choice("mikktspace".into()),
    );
    set(&mut renderer, "colour view", SetTo::Choice("normal".into()));
    let k = renderer.host.scene.control_index("compare view").unwrap();
    let reason = renderer.host.scene.controls()[k].inert.expect("a reason");
    assert!(reason.contains("colour view"), "{reason}");
    assert!(renderer.host.scene.key('K').unwrap());
    assert!(renderer.scene_ref::<Cylinder>().compare_view().is_none());
    // The lit picture compares.
    set(&mut renderer, "colour view", SetTo::Choice("lit".into()));
    assert!(renderer.host.scene.controls()[k].inert.is_none());
    assert!(renderer.host.scene.key('K').unwrap());
    assert!(renderer.scene_ref::<Cylinder>().compare_view().is_some());
}

// Fails if the command line combines --tangents derivative with flags the per-pixel frame ignores
// without a warning naming each once, with the reason its control's table gives (--green, which
// several scenes share, as --view), or if such a run does not draw the per-pixel frame of `lit`
// (exit 0, the same picture as without the flags); or if --compare of a colour view against the
// per-pixel frame (which draws none) does not say so.
#[test]
fn flags_the_per_pixel_frame_ignores_are_warned_of() {
    let dir = scratch("table-derivative-flags");
    let plain = headless_screenshot(&dir, "plain.png", &["--tangents", "derivative"]);
    let shot = dir.join("flags.png");
    let out = run(tutorial13()
        .args(["--headless", "--screenshot", "flags.png"])
        .args([
            "--tangents",
            "derivative",
            "--green",
            "down",
            "--view",
            "normal",
        ])
        .current_dir(&dir));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stderr = text(&out.stderr);
    let warning = |start: &str| {
        let line = stderr.lines().find(|l| l.contains(start));
        line.unwrap_or_else(|| panic!("no warning {start:?}: {stderr}"))
    };
    // --view is the colour view's flag in the table, --green the green switch's: each says why it
    // does nothing.
    for flag in ["--view: ", "--green: "] {
        assert!(
            warning(flag).contains("the per-pixel frame (F = derivative) draws the lit picture"),
            "{stderr}"
        );
    }
    // Once each, though --view starts two controls (the colour view and its component).
    for flag in ["--view", "--green"] {
        let lines = stderr.lines().filter(|l| l.contains(flag)).count();
        assert_eq!(lines, 1, "{flag}: {stderr}");
    }
    let flags = image::open(&shot).unwrap().to_rgb8();
    assert!(flags == plain, "the flags changed the per-pixel frame");
    // A compare view of a colour view against the per-pixel frame says it compares unlike pictures.
    let out = run(tutorial13()
        .args([
            "--headless",
            "--screenshot",
            "compare.png",
            "--view",
            "normal",
        ])
        .args(["--compare", "mikktspace,derivative"])
        .current_dir(&dir));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stderr = text(&out.stderr);
    assert!(
        stderr
            .lines()
            .any(|l| l.contains("--compare: a colour view is on")),
        "{stderr}"
    );
    // Green down alone, through the options: the same warning's cause, nothing else.
    let options = derivative_options(|o| {
        o.start(cylinder::GREEN_DOWN.to(true));
    });
    assert!(render(&options) == plain);
}

/// A quad of side 4 facing +z around x = 10 in a model's own coordinates (placed elsewhere in the
/// world), with normals and texture coordinates.
const OFF_CENTRE_QUAD: &str = "v 8 -2 0\nv 12 -2 0\nv 12 2 0\nv 8 2 0\n\
    vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
    f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";

// Fails if the light's sliders of a model are not in the model's own coordinates, as --light is
// (--light 3,0,2 must show 3, 0, 2), if moving one to a value does not give the frame of --light
// with that value bit for bit, or if their start (the tutorial's values) is --light's and not the
// tutorial's light: set to their starts, the frame must be the one without --light, bit for bit.
#[test]
fn a_models_light_sliders_are_in_the_space_of_light() {
    let dir = scratch("table-model-light");
    let model = dir.join("quad.obj");
    std::fs::write(&model, OFF_CENTRE_QUAD).unwrap();
    let with_light = |light: Option<[f32; 3]>| {
        let mut options = HeadlessOptions::default();
        cylinder_files(&mut options).model = Some(model.clone());
        if let Some(light) = light {
            options.scene = options.scene.starting(cylinder::light_at(light.into()));
        }
        options
    };
    // Rendered first: each renderer has a context of its own, current while it is built.
    let expected = render(&with_light(Some([3.0, 1.5, 2.0])));
    let tutorials = render(&with_light(None));
    let mut renderer = renderer(&with_light(Some([3.0, 0.0, 2.0])));
    let first = frame(&mut renderer);
    let axes = ["light x", "light y", "light z"];
    let index = axes.map(|a| renderer.host.scene.control_index(a).unwrap());
    let shown = |renderer: &HeadlessRenderer| {
        index.map(|i| match renderer.host.scene.controls()[i].value {
            ControlValue::Slider { value, start, .. } => (value, start),
            _ => panic!("no slider"),
        })
    };
    let values = shown(&renderer).map(|(value, _)| value);
    assert_eq!(values, [3.0, 0.0, 2.0]);
    renderer
        .host
        .scene
        .set_control(index[1], SetTo::Slider(1.5))
        .unwrap();
    let moved = frame(&mut renderer);
    assert!(
        differing_pixels(&moved, &first) > 0,
        "the light did not move"
    );
    assert_eq!(differing_pixels(&moved, &expected), 0);
    renderer
        .host
        .scene
        .set_control(index[1], SetTo::Slider(0.0))
        .unwrap();
    assert!(frame(&mut renderer) == first);
    for (i, (_, start)) in index.into_iter().zip(shown(&renderer)) {
        renderer
            .host
            .scene
            .set_control(i, SetTo::Slider(start))
            .unwrap();
    }
    assert_eq!(differing_pixels(&frame(&mut renderer), &tutorials), 0);
}

/// The panel's frame with the pointer resting at `pos` (tooltips without egui's half-second delay:
/// headless time stands still), and without any pointer.
fn hovered_and_plain(
    renderer: &mut HeadlessRenderer,
    pos: egui::Pos2,
) -> (image::RgbImage, image::RgbImage) {
    let panel = renderer.host.panel().unwrap();
    panel
        .context()
        .global_style_mut(|style| style.interaction.tooltip_delay = 0.0);
    let plain = frame(renderer);
    let at = glam::Vec2::new(pos.x, pos.y);
    renderer.event(Event::PointerMoved(at)).unwrap();
    renderer.render().unwrap();
    let hovered = frame(renderer);
    renderer.event(Event::PointerLeft).unwrap();
    (hovered, plain)
}

/// The bounding box of the pixels that differ between `a` and `b` outside `rect`, if any.
fn changed_outside(
    a: &image::RgbImage,
    b: &image::RgbImage,
    rect: egui::Rect,
) -> Option<(u32, u32, u32, u32)> {
    let mut bbox: Option<(u32, u32, u32, u32)> = None;
    for (x, y, p) in a.enumerate_pixels() {
        let inside = rect.contains(egui::pos2(x as f32 + 0.5, y as f32 + 0.5));
        if inside || p == b.get_pixel(x, y) {
            continue;
        }
        bbox = Some(match bbox {
            None => (x, y, x, y),
            Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
        });
    }
    bbox
}

/// The brightest pixel's lift above the most common one (the row's background) within `rect`.
fn text_lift(image: &image::RgbImage, rect: egui::Rect) -> (f32, [u8; 3]) {
    let luma =
        |p: &image::Rgb<u8>| 0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32;
    let mut counts = std::collections::HashMap::new();
    let mut pixels = Vec::new();
    for y in rect.min.y.ceil() as u32..rect.max.y.floor() as u32 {
        for x in rect.min.x.ceil() as u32..rect.max.x.floor() as u32 {
            let p = *image.get_pixel(x, y);
            *counts.entry(p.0).or_insert(0) += 1;
            pixels.push(p);
        }
    }
    let background = counts.into_iter().max_by_key(|&(_, n)| n).unwrap().0;
    let lift = pixels
        .iter()
        .map(|p| luma(p) - luma(&image::Rgb(background)))
        .fold(0.0, f32::max);
    (lift, background)
}

// Fails if a control that does nothing now is not drawn greyed (egui's disabled look: its text
// lifted above the row's background by half as much as the same control's where it applies,
// within 0.4 to 0.6), or if resting the pointer on it shows no tooltip, or a tooltip that is not
// the size of its reason's text, or if a control that applies shows one.
#[test]
fn greyed_controls_look_greyed_and_say_why_on_hover() {
    // One renderer at a time: each makes its own context current when it is made.
    let look = |options: &HeadlessOptions| {
        let mut r = renderer(options);
        r.host.show_panel().unwrap();
        frame(&mut r);
        let rect = r
            .host
            .panel()
            .unwrap()
            .widget_rect(&PanelWidget::Key('L'))
            .unwrap();
        let shot = frame(&mut r);
        let (hovered, plain) = hovered_and_plain(&mut r, rect.center());
        let tooltip = changed_outside(&hovered, &plain, rect);
        let control = r
            .host
            .scene
            .controls()
            .into_iter()
            .find(|c| c.key == Some('L'))
            .unwrap();
        let panel = r.host.panel().unwrap();
        let style = panel.context().global_style();
        let font = egui::TextStyle::Body.resolve(&style);
        // The reason laid out as the tooltip lays it out: wrapped at its width inside its margin.
        let margin = style.spacing.menu_margin.sum().y / 2.0;
        let reason_height = control.inert.zip(tooltip).map(|(reason, (x0, _, x1, _))| {
            let wrap = (x1 - x0 + 1) as f32 - 2.0 * margin;
            panel.context().fonts_mut(|f| {
                f.layout(reason.to_string(), font, egui::Color32::WHITE, wrap)
                    .size()
                    .y
            })
        });
        (
            rect,
            text_lift(&shot, rect),
            tooltip,
            reason_height.map(|h| h + 2.0 * margin),
        )
    };
    let (rect_on, (lift_on, _), no_tooltip, _) = look(&options(own_assets(), Profile::Core));
    let (rect, (lift_off, _), tooltip, expected_height) = look(&derivative_options(|_| {}));
    println!(
        "L's text above its row: {lift_on} levels where it applies, {lift_off} greyed; \
         tooltip {tooltip:?}, {expected_height:?} high by its reason"
    );
    assert_eq!(rect_on, rect, "L's row moved");
    let ratio = lift_off / lift_on;
    assert!(
        (0.4..=0.6).contains(&ratio),
        "greyed at {ratio} of its brightness"
    );
    assert_eq!(no_tooltip, None, "L shows a tooltip where it applies");
    let (_, y0, _, y1) = tooltip.expect("no tooltip on the greyed L");
    // egui puts a tooltip 4 points below its widget.
    assert!(
        (y0 as f32 - (rect.max.y + 4.0)).abs() <= 1.0,
        "tooltip at y {y0}"
    );
    let height = (y1 - y0 + 1) as f32;
    let expected = expected_height.unwrap();
    assert!(
        (height - expected).abs() <= 1.0,
        "the tooltip is {height} high, its reason's text needs {expected}"
    );
}

// Fails if a toggle's command-line flag is not its table's: each flag a table declares, given on
// the command line, must start its scene with that control at the flag's value, and without the
// flag the control must start the other way (else the flag would do nothing). The flags are parsed
// as the binary parses them (`scenes::command_line`, `scenes::scene_options`).
#[test]
fn each_toggles_flag_starts_it_through_the_table() {
    let mut checked = 0;
    for scene in SCENES {
        let plain = renderer(&HeadlessOptions {
            descriptor: scene,
            ..Default::default()
        });
        let controls = plain.host.scene.controls();
        drop(plain);
        for control in controls.iter() {
            let Some((flag, value)) = control.flag.and_then(|f| Some((f, f.toggle_value()?)))
            else {
                continue;
            };
            let long = format!("--{}", flag.long);
            assert_eq!(
                control.value,
                ControlValue::Toggle(!value),
                "{scene}: {long} would change nothing"
            );
            let command = tutorial13::scenes::command_line(clap::Command::new("t"));
            let matches = command.get_matches_from(["t", long.as_str()]);
            let options = tutorial13::scenes::scene_options(&matches, scene, Default::default())
                .unwrap_or_else(|e| panic!("{scene} {long}: {e}"));
            let flagged = renderer(&HeadlessOptions {
                descriptor: scene,
                scene: options,
                ..Default::default()
            });
            let value_of_flag = value;
            let value = &flagged.host.scene.controls()[control.index].value;
            assert_eq!(
                *value,
                ControlValue::Toggle(value_of_flag),
                "{scene}: {long} did not start \"{}\" {}",
                control.label,
                value_of_flag
            );
            checked += 1;
        }
    }
    // The cylinder's eight, the cube's --no-normal-map and the sprite's --independent-falloff.
    assert_eq!(checked, 10);
}

// Fails if a command-line flag with a value is not its control's in the table: each such flag (a
// choice's, a slider's, or a flag several scenes share: --green, --light, --light-power), given a
// value, must start its control at exactly that value through the table (a slider's past the
// panel's range too: --normal-strength 8 where the slider stops at 4), and every flag of that kind
// in every table must be one of the cases (so a new one cannot go unchecked).
#[test]
fn each_value_flag_starts_its_control_through_the_table() {
    /// What the control must start at: a choice's name, or a slider's value.
    #[derive(Debug)]
    enum Expect {
        Toggle(bool),
        Choice(&'static str),
        Slider(f32),
    }
    use Expect::{Choice, Slider, Toggle};
    let pair = ["--compare", "tutorial,mikktspace"];
    let light = ["--light", "1,2,3"];
    // One case a line: the scene, its flags, the control's label, the start expected.
    #[rustfmt::skip]
    let cases: [(&str, &[&str], &str, Expect); 24] = [
        ("cylinder", &["--debug-lines-mode", "shader"], "lines drawn with", Choice("line shader")),
        ("cylinder", &["--view", "normal01.y"], "colour view", Choice("normal01")),
        ("cylinder", &["--view", "normal01.y"], "component", Choice("y")),
        ("cylinder", &["--tangents", "mikktspace"], "tangent frame", Choice("mikktspace")),
        ("cylinder", &["--normal-strength", "8"], "normal strength", Slider(8.0)),
        ("cylinder", &["--line-length", "0.25"], "TBN line length", Slider(0.25)),
        ("cylinder", &[pair[0], pair[1], "--split", "0.3"], "compare split", Slider(0.3)),
        ("cylinder", &pair, "compare view", Choice("side by side")),
        ("cylinder", &[pair[0], pair[1], "--compare-difference"], "compare view", Choice("difference")),
        ("wall", &["--space", "tangent"], "lighting space", Choice("tangent")),
        ("cylinder", &["--green", "down"], "green down (DirectX)", Toggle(true)),
        ("sprite", &["--green", "down"], "green flipped", Toggle(true)),
        ("cylinder", &light, "light x", Slider(1.0)),
        ("cylinder", &light, "light y", Slider(2.0)),
        ("cylinder", &light, "light z", Slider(3.0)),
        ("cylinder", &["--light-power", "80"], "light power", Slider(80.0)),
        ("cube", &light, "light x", Slider(1.0)),
        ("cube", &light, "light y", Slider(2.0)),
        ("cube", &light, "light z", Slider(3.0)),
        ("cube", &["--light-power", "2"], "light power", Slider(2.0)),
        ("wall", &light, "light x", Slider(1.0)),
        ("wall", &light, "light y", Slider(2.0)),
        ("wall", &light, "light z", Slider(3.0)),
        ("wall", &["--light-power", "30"], "light power", Slider(30.0)),
    ];
    let check = |expect: &Expect, value: &ControlValue| match (expect, value) {
        (Toggle(on), ControlValue::Toggle(value)) => value == on,
        (Choice(name), ControlValue::Choice { current, .. }) => current == name,
        (Slider(expected), ControlValue::Slider { value, .. }) => value == expected,
        _ => false,
    };
    let mut flagged_controls = std::collections::BTreeSet::new();
    for (name, args, label, expect) in &cases {
        let scene = SCENES.iter().find(|s| s.name == *name).unwrap();
        let command = tutorial13::scenes::command_line(clap::Command::new("t"));
        let matches = command.get_matches_from(std::iter::once("t").chain(args.iter().copied()));
        let options = tutorial13::scenes::scene_options(&matches, scene, Default::default())
            .unwrap_or_else(|e| panic!("{name} {args:?}: {e}"));
        // A compatibility context, where the lines start in immediate mode.
        let start = |scene_options| {
            let renderer = renderer(&HeadlessOptions {
                descriptor: scene,
                profile: Profile::Compat,
                scene: scene_options,
                ..Default::default()
            });
            renderer.host.scene.controls()
        };
        let (plain, flagged) = (start(Default::default()), start(options));
        let index = plain.iter().position(|c| c.label == *label).unwrap();
        assert!(
            !check(expect, &plain[index].value),
            "{name}: {args:?} would change nothing"
        );
        assert!(
            check(expect, &flagged[index].value),
            "{name} {args:?}: \"{label}\" started {:?}",
            flagged[index].value
        );
        flagged_controls.insert((*name, *label));
    }
    let mut declared = std::collections::BTreeSet::new();
    for scene in SCENES {
        let plain = renderer(&HeadlessOptions {
            descriptor: scene,
            ..Default::default()
        });
        for control in plain.host.scene.controls() {
            if control.flag.is_some_and(|f| f.toggle_value().is_none()) {
                declared.insert((scene.name, control.label));
            }
        }
    }
    assert_eq!(flagged_controls, declared);
}

// Fails if --tangents builds a model's mesh twice: it is key F's flag, set through the table once the
// scene is built, but the scene reads it first and builds the model's mesh for it straight away
// (seconds on a large model), so the table's set finds it done and no mesh is built after the load.
#[test]
fn a_models_tangents_flag_builds_its_mesh_once() {
    let dir = scratch("table-tangents-once");
    let model = dir.join("quad.obj");
    std::fs::write(&model, OFF_CENTRE_QUAD).unwrap();
    let model = model.to_str().unwrap();
    let command = tutorial13::scenes::command_line(clap::Command::new("t"));
    let matches = command.get_matches_from(["t", "--model", model, "--tangents", "mikktspace"]);
    let scene = tutorial13::scenes::descriptor::<Cylinder>();
    let options = tutorial13::scenes::scene_options(&matches, scene, Default::default()).unwrap();
    let renderer = renderer(&HeadlessOptions {
        scene: options,
        ..Default::default()
    });
    let cylinder = renderer.scene_ref::<Cylinder>();
    let frame = cylinder
        .controls()
        .into_iter()
        .find(|c| c.label == "tangent frame");
    assert_eq!(frame.unwrap().value.shown(), "mikktspace");
    assert_eq!(
        cylinder.meshes_built(),
        [],
        "a mesh was built after the load"
    );
}
