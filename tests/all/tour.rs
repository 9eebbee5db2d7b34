//! The tour of the tutorial's sections: every excerpt it shows resolves in the source the binary is
//! built from, every step's frame is the frame of its switches set by flags (or its golden), stepping
//! forward and back restores each state, `--tour` answers as its help says, and the exercise check
//! tells a matching frame from an untouched one and from a wrong one.

use std::path::Path;

use image::RgbImage;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::mesh::{Code, MeshOptions};
use tutorial13::scenes::cylinder::Cylinder;
use tutorial13::scenes::{self, SceneOptions};
use tutorial13::tour::{self, Camera, STEPS};

use crate::cli::{assert_one_line_failure, assert_success};
use crate::common::{self, run, text, tutorial13};

/// Each step's frame, by its name: the frame of these flags (`--scene` picks the scene), or, where
/// the camera has moved (no flag moves it), the golden `tests/golden/tour-<name>.png`.
const FLAGS: [(&str, Option<&[&str]>); 18] = [
    ("normal-textures", Some(&["--view", "normal01"])),
    ("tangent-and-bitangent", Some(&["--debug-lines"])),
    ("computing-tangents", Some(&[])),
    ("indexing", Some(&["--debug-lines", "--line-length", "0.3"])),
    ("buffers-and-uniforms", Some(&[])),
    ("vertex-shader", Some(&["--view", "light01"])),
    ("fragment-shader", Some(&[])),
    ("results", Some(&[])),
    (
        "orthogonalization",
        Some(&["--no-gram-schmidt", "--debug-lines"]),
    ),
    ("handedness", Some(&["--no-handedness"])),
    ("specular-texture", Some(&["--no-specular-texture"])),
    ("immediate-mode", None),
    ("colors", Some(&["--view", "light.z"])),
    ("variable-names", Some(&[])),
    (
        "create-a-normal-map",
        Some(&["--view", "normal01", "--normal-strength", "2"]),
    ),
    ("exercise-1", Some(&[])),
    ("exercise-2", Some(&[])),
    ("tools-and-links", Some(&["--scene", "sprite"])),
];

/// The first frame of a scene started with `args` as the command line gives them (`--scene NAME`
/// among them picks the scene).
fn frame_of_flags(args: &[&str]) -> RgbImage {
    let command = scenes::command_line(clap::Command::new("t"));
    let scene_name = args
        .windows(2)
        .find(|w| w[0] == "--scene")
        .map_or("cylinder", |w| w[1]);
    let args: Vec<&str> = args
        .iter()
        .copied()
        .filter(|a| *a != "--scene" && *a != scene_name)
        .collect();
    let matches = command
        .try_get_matches_from(std::iter::once("t").chain(args.iter().copied()))
        .unwrap_or_else(|e| panic!("{args:?}: {e}"));
    let descriptor = scenes::find(scene_name).unwrap();
    let options = scenes::scene_options(&matches, descriptor, project_assets())
        .unwrap_or_else(|e| panic!("{args:?}: {e}"));
    common::frame(&mut common::renderer(&HeadlessOptions {
        descriptor,
        scene: options,
        ..Default::default()
    }))
}

fn project_assets() -> SceneOptions {
    SceneOptions {
        assets: Some(common::own_assets()),
        ..Default::default()
    }
}

/// The cylinder, headless, on this project's own assets.
fn cylinder_renderer() -> HeadlessRenderer {
    HeadlessRenderer::new(&HeadlessOptions {
        scene: project_assets(),
        ..Default::default()
    })
    .unwrap()
}

// Fails if a step names a Rust item or a shader region that is not in the source the binary is
// built from (renamed, removed, or its marker comments gone), or one that resolves to nothing:
// seen failing with `is_near` renamed in src/common/vboindexer.rs ("common::vboindexer::is_near:
// not found in src/common/vboindexer.rs"). Also fails if a step has no code at all, or a C++ range
// that runs backwards.
#[test]
fn every_excerpt_resolves_in_the_built_source() {
    let mut missing = Vec::new();
    for step in &STEPS {
        let excerpts = step.excerpts();
        assert!(
            !excerpts.is_empty() || !step.cpp.is_empty(),
            "step {} ({}) shows no code",
            step.number(),
            step.section
        );
        for (asked, found) in excerpts {
            match found {
                Ok(excerpt) => {
                    let (first, last) = excerpt.lines;
                    assert!(first <= last && !excerpt.text.trim().is_empty(), "{asked}");
                    assert_eq!(excerpt.text.lines().count(), last - first + 1, "{asked}");
                }
                Err(why) => missing.push(format!("step {}: {why}", step.number())),
            }
        }
        for cpp in step.cpp {
            assert!(cpp.lines.0 <= cpp.lines.1, "{}", cpp.label());
            assert!(cpp
                .url()
                .ends_with(&format!("#L{}-L{}", cpp.lines.0, cpp.lines.1)));
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

// Fails if an excerpt's text is not the lines it claims in the file on disk (the resolver counting
// lines wrong, or the binary built from another text than the checkout's), or if a Rust item's
// excerpt does not start at its doc comment or definition and end at its closing line.
#[test]
fn excerpts_are_the_lines_they_name() {
    for step in &STEPS {
        for (asked, found) in step.excerpts() {
            let excerpt = found.unwrap_or_else(|why| panic!("{why}"));
            let file = std::fs::read_to_string(common::manifest().join(&excerpt.file)).unwrap();
            let lines: Vec<&str> = file.lines().collect();
            let (first, last) = excerpt.lines;
            assert_eq!(lines[first - 1..last].join("\n"), excerpt.text, "{asked}");
            if !asked.contains(" #") {
                let head = excerpt.text.lines().next().unwrap().trim_start();
                let tail = excerpt.text.lines().last().unwrap().trim();
                assert!(
                    head.starts_with("///") || head.starts_with("#[") || head.contains(' '),
                    "{asked}: starts with {head:?}"
                );
                assert!(
                    tail.ends_with('}') || tail.ends_with(';'),
                    "{asked}: ends with {tail:?}"
                );
            }
        }
    }
}

// Fails if a step's frame is not the frame of its switches set by their flags (a label the table
// does not have, a value set otherwise than the flag sets it, a scene not built fresh), or, for
// the step whose camera moved, not its golden; and if stepping back does not restore a step
// exactly (a switch from a later step left on): the tour is walked forward, then back, on one
// renderer, each frame compared with the frame of a renderer started fresh.
#[test]
fn every_step_draws_its_flags_frame_forward_and_back() {
    let expected: Vec<Option<RgbImage>> = FLAGS
        .iter()
        .zip(&STEPS)
        .map(|((name, flags), step)| {
            assert_eq!(*name, step.name, "FLAGS is in the tour's order");
            assert_eq!(
                flags.is_none(),
                step.state.camera != Camera::Start,
                "{name}: a golden where, and only where, the camera moved"
            );
            flags.map(frame_of_flags)
        })
        .collect();
    let mut renderer = cylinder_renderer();
    let order: Vec<usize> = (0..STEPS.len()).chain((0..STEPS.len()).rev()).collect();
    let mut golden_visits = Vec::new();
    for (visit, &i) in order.iter().enumerate() {
        let step = &STEPS[i];
        renderer.host.show_step(step).unwrap();
        let frame = common::frame(&mut renderer);
        match &expected[i] {
            Some(flags) => {
                let d = common::frame_diff(flags, &frame);
                assert_eq!(
                    d.differing(),
                    0,
                    "step {} ({}), visit {visit}: {} pixels differ from its flags' frame (max {}, \
                     within {:?})",
                    i + 1,
                    step.name,
                    d.differing(),
                    d.max(),
                    d.bbox
                );
            }
            // Compared once the walk is done: the golden check makes a context of its own current.
            None => golden_visits.push((step.name, frame)),
        }
    }
    for (name, frame) in golden_visits {
        common::assert_matches_golden(&frame, &format!("tour-{name}"));
    }
}

// Fails if `--tour list` does not print one line per step, its number and its section, in the
// tour's order, or if `--tour N --headless` does not draw step N (its frame must be the in-process
// step's, here the orthogonalization step's switches).
#[test]
fn tour_list_and_a_step_from_the_command_line() {
    let out = run(tutorial13().args(["--tour", "list"]));
    assert_success(&out, "--tour list");
    let listed = text(&out.stdout);
    let expected: String = STEPS
        .iter()
        .enumerate()
        .map(|(i, s)| format!("{:>2}  {}\n", i + 1, s.section))
        .collect();
    assert_eq!(listed, expected);
    assert_eq!(listed.lines().count(), 18);

    let dir = common::scratch("step");
    let shot = common::headless_screenshot(
        &dir,
        "nine.png",
        &[
            "--tour",
            "9",
            "--assets",
            &common::own_assets().to_string_lossy(),
        ],
    );
    let step = tour::find("orthogonalization").unwrap();
    assert_eq!(step.number(), 9);
    let mut renderer = cylinder_renderer();
    renderer.host.set_step_state(step).unwrap();
    assert_eq!(
        common::differing_pixels(&common::frame(&mut renderer), &shot),
        0
    );
}

// Fails if a bad `--tour` value (out of range, zero, an unknown name) is anything but one line on
// stderr and a non-zero exit (the window's path: tests/all/tour_pane.rs).
#[test]
fn bad_tour_values_are_one_line_errors() {
    for value in ["0", "19", "normal-texture", "1.5"] {
        let out = run(tutorial13().args(["--headless", "--tour", value]));
        let line = assert_one_line_failure(&out, &format!("--tour {value}"));
        assert!(line.contains(&format!("--tour {value}")), "{line}");
    }
}

// Fails if `--check-exercise` takes a flag it would ignore (`--screenshot`: no file written, the
// script told nothing; `--frames`) instead of refusing it as a usage error (clap's, exit 2) before
// anything is drawn or written.
#[test]
fn check_exercise_refuses_the_flags_it_would_ignore() {
    let shot = common::scratch("check-exercise").join("never.png");
    let shot_arg = shot.to_string_lossy();
    for flag in [["--screenshot", &*shot_arg], ["--frames", "2"]] {
        let out = run(tutorial13()
            .args(["--headless", "--check-exercise", "1"])
            .args(flag));
        assert_eq!(out.status.code(), Some(2), "{flag:?}");
        let err = text(&out.stderr);
        assert!(err.contains("cannot be used with"), "{flag:?}: {err}");
        assert!(err.contains(flag[0]), "{flag:?}: {err}");
    }
    assert!(!shot.exists());
}

// Fails if a state names a control its scene's table does not have, or a value the control does
// not take (a choice's name it lacks, a slider's value outside its range, a switch's value on a
// choice), and the table's own leniency (it logs and ignores an unknown name, clamps a slider)
// lets the step draw something else than it says, or if a good state is refused.
#[test]
fn a_state_the_table_cannot_take_is_an_error() {
    let mut renderer = cylinder_renderer();
    let state = |controls| tour::State {
        scene: "cylinder",
        controls,
        camera: Camera::Start,
    };
    let bad: [&'static [(&str, tour::Value)]; 4] = [
        &[("colour view", tour::Value::Choice("purple"))],
        &[("colour vue", tour::Value::Choice("eye"))],
        &[("normal strength", tour::Value::Slider(9.0))],
        &[("colour view", tour::Value::On(true))],
    ];
    for controls in bad {
        let error = state(controls)
            .set_controls(renderer.host.scene.as_mut())
            .unwrap_err()
            .to_string();
        assert!(error.contains(controls[0].0), "{error}");
    }
    state(&[("colour view", tour::Value::Choice("eye"))])
        .set_controls(renderer.host.scene.as_mut())
        .unwrap();
}

/// The cylinder's first frame with the CPU pipeline's `mesh` options set after it is built.
fn cylinder_frame_with(renderer: &mut HeadlessRenderer, mesh: MeshOptions) -> RgbImage {
    renderer
        .scene_mut::<Cylinder>()
        .set_mesh_options(mesh)
        .unwrap();
    common::frame(renderer)
}

// Fails if exercise 1's reference (the fast twin with the N switch's normalization) is not the
// frame of --normalize-before-sum, if the port normalizing before summing (what a learner's edit of
// index_vbo_tbn makes) does not draw that reference to the bit, or if the check of an unedited
// build does not say "not done yet" and exit non-zero.
#[test]
fn exercise_1_reference_is_the_n_switch_and_an_unedited_build_is_not_done() {
    let mut renderer = cylinder_renderer();
    let normalized = |code| MeshOptions {
        code: Some(code),
        indexing: tutorial13::common::vboindexer::IndexOptions {
            normalize_before_sum: true,
        },
        ..MeshOptions::default()
    };
    let reference = cylinder_frame_with(&mut renderer, normalized(Code::FastTwins));
    let edited_port = cylinder_frame_with(&mut renderer, normalized(Code::Ports));
    let unchanged = cylinder_frame_with(&mut renderer, MeshOptions::default());
    assert_eq!(common::differing_pixels(&reference, &edited_port), 0);
    assert_eq!(
        common::differing_pixels(&reference, &frame_of_flags(&["--normalize-before-sum"])),
        0
    );
    assert!(common::differing_pixels(&reference, &unchanged) > 0);

    let out = run(tutorial13().args(["--headless", "--check-exercise", "1"]));
    let line = failure_line(&out, "--check-exercise 1, unedited");
    assert!(line.contains("exercise 1: not done yet"), "{line}");
    assert!(line.contains("src/common/vboindexer.rs"), "{line}");
}

/// The last line of a failed run's stderr (after the log's), which must be the program's error.
fn failure_line(out: &std::process::Output, what: &str) -> String {
    assert!(
        !out.status.success(),
        "{what}: exit 0\n{}",
        text(&out.stdout)
    );
    let stderr = text(&out.stderr);
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    let line = stderr.lines().last().unwrap_or_default().to_string();
    assert!(line.starts_with("tutorial13: "), "{what}: {stderr}");
    line
}

/// A copy of the crate's shaders in `dir`, with NormalMapping.fragmentshader's last statement
/// followed by `colour` (`None`: unchanged).
pub(crate) fn shaders_with_colour(dir: &Path, colour: Option<&str>) {
    for (name, text) in tutorial13::common::shader::embedded_shaders() {
        let text = match (colour, *name == "NormalMapping.fragmentshader") {
            (Some(colour), true) => {
                let end = text.rfind('}').unwrap();
                format!("{}    color = {colour};\n}}\n", &text[..end])
            }
            _ => text.to_string(),
        };
        std::fs::write(dir.join(name), text).unwrap();
    }
}

// Fails if exercise 2 done as asked (the fragment shader's colour the normalized eye direction, in a
// --shaders copy) does not match the colour view "eye" and exit 0 with "matches" on stdout; if an
// unedited copy is not told "not done yet"; or if a wrong edit (the eye direction not normalized) is
// not told how many pixels differ and where, with a non-zero exit.
#[test]
fn exercise_2_is_checked_against_the_eye_view() {
    let check = |name: &str, colour: Option<&str>| {
        let dir = common::scratch(name);
        shaders_with_colour(&dir, colour);
        run(tutorial13()
            .args(["--headless", "--check-exercise", "2", "--shaders"])
            .arg(&dir))
    };
    let done = check("done", Some("normalize(EyeDirection_tangentspace)"));
    assert_success(&done, "exercise 2 done");
    let line = text(&done.stdout);
    assert!(line.starts_with("exercise 2: matches"), "{line}");
    assert_eq!(line.lines().count(), 1);

    let untouched = failure_line(&check("untouched", None), "exercise 2 untouched");
    assert!(
        untouched.contains("exercise 2: not done yet"),
        "{untouched}"
    );

    let wrong = failure_line(
        &check("wrong", Some("EyeDirection_tangentspace")),
        "exercise 2 unnormalized",
    );
    assert!(
        wrong.contains("pixels differ from the reference") && wrong.contains("within x "),
        "{wrong}"
    );
}
