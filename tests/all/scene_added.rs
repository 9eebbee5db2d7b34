//! What adding a scene takes, as the reading guide's "How to add a scene" says: one type with
//! `Scene::draw` and `SceneType` (its name, description, GL state, table of controls and `new`).
//! Everything else (its descriptor, key list, flags and their `--help` heading, its starts, the
//! headless front end running it) follows from those. In the crate it would be a folder
//! `src/scenes/solid/` and one line in `SCENES`; here its descriptor is a static of its own.

use glow::HasContext;
use image::Rgb;
use tutorial13::frontends::headless::HeadlessOptions;
use tutorial13::gl::state::GlState;
use tutorial13::gl::Gl;
use tutorial13::scenes::{
    Control, FrameInput, Handle, KeyHelp, MouseMode, Scene, SceneContext, SceneDescriptor,
    SceneOptions, SceneType, Starts,
};

use crate::common::{frame, renderer};

/// The whole frame in one colour: green, or blue with its switch, at a level its slider sets.
struct Solid {
    gl: Gl,
    blue: bool,
    level: f32,
}

/// Its switch (key X, flag `--blue`) and its slider (flag `--level`).
const CONTROLS: &[C] = &[
    C::toggle(
        'X',
        "blue",
        "the frame green / blue",
        |s| s.blue,
        |s, on| {
            s.blue = on;
            Ok(())
        },
    )
    .flag("blue", true, "Start blue"),
    C::slider(
        "level",
        |_| (0.0, 1.0),
        |_| 0.5,
        |s| s.level,
        |s, level| {
            s.level = level;
            Ok(())
        },
    )
    .value_flag(
        "level",
        "L",
        "The colour's level, 0 to 1",
        Some(|arg| arg.value_parser(clap::value_parser!(f32))),
        tutorial13::scenes::flags::read_slider,
    ),
];

/// A control of this scene.
type C = Control<Solid>;

/// The typed handles a caller starts them through.
const BLUE: Handle<Solid, bool> = Handle::new(CONTROLS, "blue");
const LEVEL: Handle<Solid, f32> = Handle::new(CONTROLS, "level");

impl Scene for Solid {
    fn draw(&mut self, _: &FrameInput) {
        let (green, blue) = match self.blue {
            true => (0.0, self.level),
            false => (self.level, 0.0),
        };
        // SAFETY: clearing the bound framebuffer of the current context.
        unsafe {
            self.gl.clear_color(0.0, green, blue, 1.0);
            self.gl.clear(glow::COLOR_BUFFER_BIT);
        }
    }
}

impl SceneType for Solid {
    const NAME: &'static str = "solid";
    const DESCRIPTION: &'static str = "One colour, switched by X";
    const GL_STATE: GlState = GlState::flat([0.0, 0.0, 0.0, 1.0]);
    const CONTROLS: &'static [Control<Self>] = CONTROLS;

    fn new(
        context: &SceneContext,
        _: &SceneOptions,
        _: &mut Starts<Self>,
    ) -> tutorial13::Result<Self> {
        Ok(Solid {
            gl: context.gl.clone(),
            blue: false,
            level: 0.5,
        })
    }
}

/// What `SCENES` would list.
static SOLID: SceneDescriptor = SceneDescriptor::of::<Solid>();

/// The frame of the scene with `options`, and the one colour it must be all over.
fn solid_frame(options: SceneOptions) -> image::RgbImage {
    let mut renderer = renderer(&HeadlessOptions {
        descriptor: &SOLID,
        scene: options,
        width: 64,
        height: 48,
        ..Default::default()
    });
    frame(&mut renderer)
}

/// Whether every pixel of `frame` is `colour`.
fn all(frame: &image::RgbImage, colour: [u8; 3]) -> bool {
    frame.pixels().all(|p| *p == Rgb(colour))
}

// Fails if a scene type alone does not give a descriptor whose name, description, mouse mode, GL
// state and key list are the type's (the list from its table, in order, with the table's words), or
// whose flags are not its table's under the heading "Scene solid" in `--help`.
#[test]
fn a_scene_types_descriptor_is_made_from_it() {
    assert_eq!(
        (SOLID.name, SOLID.description, SOLID.mouse_mode),
        ("solid", "One colour, switched by X", MouseMode::Look)
    );
    assert_eq!(SOLID.gl_state, Solid::GL_STATE);
    let keys = [KeyHelp {
        key: 'X',
        help: "the frame green / blue",
    }];
    assert_eq!(SOLID.keys, keys);
    let command = (SOLID.args)(clap::Command::new("t"));
    let flags: Vec<(&str, Option<&str>)> = command
        .get_arguments()
        .map(|arg| (arg.get_id().as_str(), arg.get_help_heading()))
        .collect();
    let heading = Some("Scene solid");
    assert_eq!(flags, [("blue", heading), ("level", heading)]);
    let help = command.get_arguments().next().unwrap().get_help().unwrap();
    assert_eq!(help.to_string(), "Start blue (key X)");
}

// Fails if the headless front end does not run a scene made from its type alone, or if its controls
// started by their flags, by their typed handles (before the scene is built, or on the running
// scene, as a step of a tour would), and by its key and table do not all draw the same frame: green
// at the slider's start (0.5: level 128), blue at 0.25 (level 64) once switched. Starts of another
// scene type must leave it alone.
#[test]
fn a_scene_types_controls_start_from_its_flags_and_handles() {
    assert!(all(&solid_frame(SceneOptions::default()), [0, 128, 0]));

    let command = (SOLID.args)(clap::Command::new("t"));
    let matches = command.get_matches_from(["t", "--blue", "--level", "0.25"]);
    let mut flagged = SceneOptions::default();
    (SOLID.read_args)(&matches, &mut flagged).unwrap();
    assert!(all(&solid_frame(flagged), [0, 0, 64]), "its flags");

    let started = SceneOptions::default().starting([BLUE.to(true), LEVEL.to(0.25)]);
    assert!(all(&solid_frame(started), [0, 0, 64]), "its handles");

    let mut renderer = renderer(&HeadlessOptions {
        descriptor: &SOLID,
        width: 64,
        height: 48,
        ..Default::default()
    });
    let step: Starts<Solid> = [BLUE.to(true), LEVEL.to(0.25)].into_iter().collect();
    let other = Starts::<tutorial13::scenes::cube::Cube>::default();
    assert!(!other.apply_to(&mut *renderer.host.scene).unwrap());
    assert!(
        all(&frame(&mut renderer), [0, 128, 0]),
        "another scene's starts"
    );
    assert!(step.apply_to(&mut *renderer.host.scene).unwrap());
    assert!(
        all(&frame(&mut renderer), [0, 0, 64]),
        "a step on the running scene"
    );

    let mut renderer = crate::common::renderer(&HeadlessOptions {
        descriptor: &SOLID,
        width: 64,
        height: 48,
        ..Default::default()
    });
    assert!(renderer.host.scene.key('x').unwrap());
    let level = renderer.host.scene.control_index("level").unwrap();
    let to = tutorial13::scenes::SetTo::Slider(0.25);
    renderer.host.scene.set_control(level, to).unwrap();
    assert!(all(&frame(&mut renderer), [0, 0, 64]), "its key and table");
    assert_eq!(renderer.host.scene.status(), "blue on | level 0.25");
}
