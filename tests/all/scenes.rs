//! The scene seam: switching scenes at run time (the window's Enter key, `switch_scene` headless)
//! frees every GL object of the scene it leaves, and a scene built again draws the same frame.

use std::num::NonZeroU32;

use glow::HasContext;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::gl::Profile;
use tutorial13::scenes::cylinder::{self, Cylinder, CylinderFiles};
use tutorial13::scenes::{descriptor, SceneOptions, SceneType, Shared, Starts, SCENES};

/// GL names in use, by kind, among the first 4096 (Mesa hands out small consecutive names).
fn live_objects(gl: &glow::Context) -> [usize; 6] {
    let mut counts = [0; 6];
    for n in (1..=4096).filter_map(NonZeroU32::new) {
        // SAFETY: glIs* queries accept any name and create nothing.
        let alive = unsafe {
            [
                gl.is_buffer(glow::NativeBuffer(n)),
                gl.is_texture(glow::NativeTexture(n)),
                gl.is_program(glow::NativeProgram(n)),
                gl.is_shader(glow::NativeShader(n)),
                gl.is_framebuffer(glow::NativeFramebuffer(n)),
                gl.is_renderbuffer(glow::NativeRenderbuffer(n)),
            ]
        };
        for (count, alive) in counts.iter_mut().zip(alive) {
            *count += usize::from(alive);
        }
    }
    counts
}

// Fails if switching scenes leaves any buffer, texture, program, shader, framebuffer or renderbuffer
// of the scene left behind alive (the count must return to its value before the switches), if a
// switch raises a GL error, or if the scene built again draws a different frame.
#[test]
fn switching_scenes_leaks_no_gl_objects() {
    for profile in [Profile::Core, Profile::Compat] {
        let mut renderer = HeadlessRenderer::new(&HeadlessOptions {
            profile,
            ..Default::default()
        })
        .unwrap();
        let first = renderer.render_frames(1).unwrap();
        let before = live_objects(&renderer.host.gl().gl);
        assert!(
            before[0] >= 6 && before[1] >= 3,
            "{before:?}: the scene holds no objects?"
        );
        // Enter, as the window's: the host builds the next scene.
        for _ in 0..3 * SCENES.len() {
            renderer.host.next_scene().unwrap();
            renderer.render_frames(1).unwrap();
        }
        assert_eq!(
            renderer.host.descriptor(),
            tutorial13::scenes::default_scene()
        );
        assert_eq!(live_objects(&renderer.host.gl().gl), before, "{profile}");
        assert!(
            renderer.render_frames(1).unwrap() == first,
            "{profile}: frame changed"
        );
    }
}

// Fails if any scene relies on GL state that another scene sets or changes (clear colour, depth test,
// culling, blending, scissor, the bound program, ...): for every ordered pair of scenes A, B, in both
// profiles, B's first frame drawn on a context where A has just drawn must equal B's frame drawn on a
// fresh context, bit for bit. The cylinder draws its TBN lines (immediate mode where the profile has
// it), the aid that changes the most state.
#[test]
fn every_scene_draws_the_same_after_any_other() {
    let mut scene_options = SceneOptions::default();
    scene_options.start(cylinder::LINES.to(true));
    for profile in [Profile::Core, Profile::Compat] {
        let options = |descriptor| HeadlessOptions {
            descriptor,
            scene: scene_options.clone(),
            width: 256,
            height: 192,
            profile,
            ..Default::default()
        };
        let alone: Vec<_> = SCENES
            .iter()
            .map(|&b| {
                let mut renderer = HeadlessRenderer::new(&options(b)).unwrap();
                renderer.render_frames(1).unwrap()
            })
            .collect();
        for &a in &SCENES {
            for (&b, alone) in SCENES.iter().zip(&alone).filter(|(&b, _)| b != a) {
                let mut renderer = HeadlessRenderer::new(&options(a)).unwrap();
                renderer.render_frames(1).unwrap();
                renderer.host.switch_scene(b).unwrap();
                let after = renderer.render_frames(1).unwrap();
                let differ = after
                    .pixels()
                    .zip(alone.pixels())
                    .filter(|(x, y)| x != y)
                    .count();
                assert_eq!(
                    differ, 0,
                    "{profile}: {b} after {a} differs in {differ} pixels"
                );
            }
        }
    }
}

/// A value `arg` accepts, for a command line that gives it.
fn some_value(arg: &clap::Arg) -> Option<String> {
    if !arg.get_action().takes_values() {
        return None;
    }
    let value = match arg.get_id().as_str() {
        "compare" => "tutorial,mikktspace".to_string(),
        "light" => "0.5,0.5,0.1".to_string(),
        "model" => "model.obj".to_string(),
        "diffuse" | "normal_map" | "specular" | "height" => "map.png".to_string(),
        "strength" => "8".to_string(),
        "normal-strength" | "line-length" | "light_power" | "split" => "0.5".to_string(),
        "view" => "normal01.y".to_string(),
        _ => match arg.get_default_values().first() {
            Some(default) => default.to_string_lossy().into_owned(),
            None => arg.get_possible_values()[0].get_name().to_string(),
        },
    };
    Some(value)
}

// Fails if any scene's flag is silently ignored by another scene: every argument of every scene's
// own list (and every shared flag) is given, alone, to every scene; the scene that reads it must
// accept it, every other scene must refuse it with a message naming the scene it belongs to.
#[test]
fn a_flag_of_another_scene_is_an_error_naming_its_scene() {
    let command = tutorial13::scenes::command_line(clap::Command::new("t"));
    let mut checked = 0;
    for owner in SCENES {
        let own = (owner.args)(clap::Command::new(owner.name));
        for arg in own.get_arguments() {
            let long = format!("--{}", arg.get_long().unwrap());
            let mut argv = vec!["t".to_string(), long.clone()];
            argv.extend(some_value(arg));
            // These two need --compare, which is then the first flag found out of place; and
            // --strength needs --height.
            let named = if arg.get_id() == "split" || arg.get_id() == "compare-difference" {
                argv.extend(["--compare".into(), "tutorial,mikktspace".into()]);
                "--compare".to_string()
            } else if arg.get_id() == "strength" {
                argv.extend(["--height".into(), "map.png".into()]);
                "--height".to_string()
            } else {
                long.clone()
            };
            let matches = command.clone().try_get_matches_from(&argv).unwrap();
            for scene in SCENES {
                let result =
                    tutorial13::scenes::scene_options(&matches, scene, SceneOptions::default());
                if scene == owner {
                    assert!(result.is_ok(), "{argv:?} on {scene}: {result:?}");
                } else {
                    let message = result.expect_err(&format!("{argv:?} accepted by {scene}"));
                    assert!(
                        message.contains(&format!("{named} is an option of scene {owner}"))
                            && message.contains(&format!("not of scene {scene}")),
                        "{message}"
                    );
                }
                checked += 1;
            }
        }
    }
    for scene in SCENES {
        let matches = command.clone().get_matches_from(["t", "--green", "down"]);
        let result = tutorial13::scenes::scene_options(&matches, scene, SceneOptions::default());
        assert_eq!(
            result.is_ok(),
            scene.shared_args.contains(&Shared::Green),
            "{scene}: {result:?}"
        );
        checked += 1;
    }
    assert!(
        checked > 60,
        "only {checked} cases: are the scenes' arguments listed?"
    );
}

// Fails if a key is found in the wrong case only, an unbound key (or a slider, which has none)
// finds a control, or a scene lists one key twice (the second control could never be reached;
// `KeyList::of` also refuses it when the crate is built).
#[test]
fn keys_find_their_controls_in_either_case() {
    use tutorial13::scenes::{control_for_key, Control};
    let none = |_: &mut u8| Ok(());
    let table: [Control<u8>; 3] = [
        Control::press('L', "lines", "lines", none),
        Control::slider("slider", |_| (0.0, 1.0), |_| 0.0, |_| 0.0, |_, _| Ok(())),
        Control::press('7', "seven", "seven", none),
    ];
    let find = |key| control_for_key(&table, key);
    assert_eq!(
        (find('l'), find('L'), find('7')),
        (Some(0), Some(0), Some(2))
    );
    assert_eq!(find('Q'), None);
    for scene in SCENES {
        let mut keys: Vec<char> = scene.keys.iter().map(|k| k.key).collect();
        keys.sort_unstable();
        keys.dedup();
        assert_eq!(keys.len(), scene.keys.len(), "{scene} lists a key twice");
        assert!(!scene.keys.is_empty(), "{scene} has no keys");
    }
}

// Fails if a shared flag's help does not name exactly the scenes whose descriptors read it (a new
// scene that reads `--green` must appear there without anyone editing the help text).
#[test]
fn a_shared_flags_help_names_its_scenes() {
    let command = tutorial13::scenes::command_line(clap::Command::new("t"));
    let green = command
        .get_arguments()
        .find(|a| a.get_id() == "green")
        .expect("--green");
    let help = green.get_help().expect("help").to_string();
    let readers: Vec<_> = SCENES
        .iter()
        .filter(|s| s.shared_args.contains(&Shared::Green))
        .map(|s| s.name)
        .collect();
    assert_eq!(readers, ["cylinder", "sprite"]);
    assert!(help.ends_with("[scenes cylinder and sprite]"), "{help}");
}

// Fails if a shared flag that only the chosen scene can take as given is refused for another
// scene's reading of it (`--light 0,0,-4` is a place below the cylinder's centre, no height over the
// sprite), or if the chosen scene's refusal is not its one message as it wrote it (once "error:
// error: …" with a blank line).
#[test]
fn only_the_chosen_scene_refuses_a_shared_flags_value() {
    let command = tutorial13::scenes::command_line(clap::Command::new("t"));
    let matches = command.get_matches_from(["t", "--light", "0,0,-4"]);
    let options =
        |scene| tutorial13::scenes::scene_options(&matches, scene, SceneOptions::default());
    let cylinder = options(descriptor::<Cylinder>()).unwrap();
    assert_eq!(
        light_started::<Cylinder>(&cylinder),
        Some(glam::Vec3::new(0.0, 0.0, -4.0))
    );
    assert_eq!(
        options(descriptor::<tutorial13::scenes::sprite::Sprite>()).unwrap_err(),
        "--light: Z = -4 must be above 0 (the light's height over the sprite)"
    );
}

/// Where the starts in `options` put the light of scene type `S` (its three sliders'), if they do.
fn light_started<S: SceneType>(options: &SceneOptions) -> Option<glam::Vec3> {
    use tutorial13::scenes::lights::LIGHT_AXES;
    use tutorial13::scenes::Handle;
    let starts = options.get::<Starts<S>>();
    let axis = |label| starts.get(Handle::<S, f32>::new(S::CONTROLS, label));
    let [x, y, z] = LIGHT_AXES.map(axis);
    Some(glam::Vec3::new(x?, y?, z?))
}

// Fails if a scene flag is accepted but not parsed into its option as given: each flag of each scene
// that no frame test reads, given a value other than its default, must show in the options the
// scene is built with, as that value.
#[test]
fn each_flag_is_parsed_into_its_option() {
    use glam::Vec3;
    use std::path::PathBuf;
    use tutorial13::debug::lines::LineMode;
    use tutorial13::scenes::cube::{self, Cube};
    use tutorial13::scenes::lights::light_power;
    use tutorial13::scenes::sprite::{self, Sprite, SpriteOptions};
    use tutorial13::scenes::wall::{self, LightingSpace, Wall};
    /// The starts the options hold for scene type `S`.
    fn starts<S: SceneType>(o: &SceneOptions) -> Starts<S> {
        o.get::<Starts<S>>()
    }
    type Check = fn(&SceneOptions) -> bool;
    let cases: [(&str, &[&str], Check); 16] = [
        ("cylinder", &["--light", "1,-2,3"], |o| {
            light_started::<Cylinder>(o) == Some(Vec3::new(1.0, -2.0, 3.0))
        }),
        ("cylinder", &["--light-power", "12.5"], |o| {
            starts::<Cylinder>(o).get(cylinder::LIGHT_POWER) == Some(12.5)
        }),
        ("cylinder", &["--debug-lines-mode", "shader"], |o| {
            starts::<Cylinder>(o).get(cylinder::LINE_MODE) == Some(LineMode::Shader)
        }),
        ("cylinder", &["--model", "a b.obj"], |o| {
            o.get::<CylinderFiles>().model == Some(PathBuf::from("a b.obj"))
        }),
        ("cylinder", &["--diffuse", "d.png"], |o| {
            o.get::<CylinderFiles>().maps.diffuse == Some(PathBuf::from("d.png"))
        }),
        ("cylinder", &["--normal-map", "n.png"], |o| {
            o.get::<CylinderFiles>().maps.normal == Some(PathBuf::from("n.png"))
        }),
        ("cylinder", &["--specular", "s.png"], |o| {
            o.get::<CylinderFiles>().maps.specular == Some(PathBuf::from("s.png"))
        }),
        (
            "cylinder",
            &["--height", "h.png", "--strength", "-3"],
            |o| {
                let maps = o.get::<CylinderFiles>().maps;
                maps.height == Some(PathBuf::from("h.png")) && maps.strength == Some(-3.0)
            },
        ),
        ("sprite", &["--light", "0.25,0.75,0.5"], |o| {
            o.get::<SpriteOptions>().light == Vec3::new(0.25, 0.75, 0.5)
        }),
        ("sprite", &["--green", "down"], |o| {
            starts::<Sprite>(o).get(sprite::GREEN_FLIPPED) == Some(true)
        }),
        ("sprite", &["--independent-falloff"], |o| {
            let starts = starts::<Sprite>(o);
            starts.settings().len() == 1 && starts.get(sprite::INDEPENDENT_FALLOFF) == Some(true)
        }),
        ("cube", &["--no-normal-map"], |o| {
            let starts = starts::<Cube>(o);
            starts.settings().len() == 1 && starts.get(cube::NORMAL_MAPPING) == Some(false)
        }),
        ("cube", &["--light", "1,2,3", "--light-power", "2"], |o| {
            let power = starts::<Cube>(o).get(light_power(Cube::CONTROLS));
            light_started::<Cube>(o) == Some(Vec3::new(1.0, 2.0, 3.0)) && power == Some(2.0)
        }),
        ("wall", &["--space", "tangent"], |o| {
            starts::<Wall>(o).get(wall::SPACE) == Some(LightingSpace::Tangent)
        }),
        ("wall", &["--light", "0,1,2", "--light-power", "7"], |o| {
            let power = starts::<Wall>(o).get(light_power(Wall::CONTROLS));
            light_started::<Wall>(o) == Some(Vec3::new(0.0, 1.0, 2.0)) && power == Some(7.0)
        }),
        ("cylinder", &["--green", "down"], |o| {
            starts::<Cylinder>(o).get(cylinder::GREEN_DOWN) == Some(true)
        }),
    ];
    for (name, args, check) in cases {
        let scene = SCENES.iter().find(|s| s.name == name).unwrap();
        let command = tutorial13::scenes::command_line(clap::Command::new("t"));
        let argv = std::iter::once("t").chain(args.iter().copied());
        let matches = command.try_get_matches_from(argv).unwrap();
        let options = tutorial13::scenes::scene_options(&matches, scene, SceneOptions::default())
            .unwrap_or_else(|e| panic!("{name} {args:?}: {e}"));
        assert!(check(&options), "{name} {args:?}: {options:?}");
        assert!(
            !check(&SceneOptions::default()),
            "{name} {args:?}: the default passes too"
        );
    }
}
