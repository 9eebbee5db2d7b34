//! The scene host: what every front end drives. It owns the scene, its descriptor, the options it
//! was built with, the tutorial's camera (`controls.cpp`) and the input that moves it, and the
//! cursor. Keys, mouse motion, the wheel, clicks and dropped files reach the scene through it; the
//! panel does not, as it reads and sets the scene's table itself ([`crate::frontends::panel`]).
//! The window, the browser page, headless rendering and the tests differ only in where the frame
//! goes and where their input comes from, so Enter, a dropped file or R does the same in each.

use std::any::Any;
use std::path::Path;

use glam::Vec2;

use crate::common::controls::{Controls, Input};
use crate::gl::extensions::GlExtensions;
use crate::gl::{ContextInfo, Gl};
use crate::scenes::{FrameInput, Scene, SceneContext, SceneDescriptor, SceneOptions};
use crate::Result;

/// An arrow key: the tutorial's camera moves while one is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arrow {
    Up,
    Down,
    Left,
    Right,
}

/// The GL context the host builds its scenes on and draws them with: the front end's, shared.
#[derive(Clone)]
struct HostContext {
    gl: Gl,
    info: ContextInfo,
    extensions: GlExtensions,
}

impl HostContext {
    fn scene_context(&self) -> SceneContext<'_> {
        SceneContext {
            gl: &self.gl,
            info: &self.info,
            extensions: &self.extensions,
        }
    }
}

/// The scene being drawn, its camera and its input.
pub struct SceneHost {
    // Field order is drop order: the scene's GL objects go first.
    /// The scene (see [`SceneHost::scene_as`] to reach a particular scene's internals).
    pub scene: Box<dyn Scene>,
    descriptor: &'static SceneDescriptor,
    /// What the scenes are built with: `--assets`, `--shaders` and each scene's own options; a
    /// dropped file changes them, Enter keeps them.
    options: SceneOptions,
    /// The tutorial's camera.
    pub controls: Controls,
    /// Arrow keys held and mouse motion since the last frame.
    input: Input,
    /// The cursor in frame pixels (x right, y down), for scenes that follow it; `None` off the
    /// frame (or over the panel).
    pub cursor: Option<Vec2>,
    /// The size of the frame the camera's projection is for.
    size: (u32, u32),
    /// What every scene it builds is built on (Enter, a dropped file).
    context: HostContext,
}

impl SceneHost {
    /// Builds `descriptor`'s scene with `options` on `context`, the camera at its start for a frame
    /// of `size`.
    pub fn new(
        context: &SceneContext,
        descriptor: &'static SceneDescriptor,
        options: &SceneOptions,
        size: (u32, u32),
    ) -> Result<Self> {
        let scene = (descriptor.build)(context, options)?;
        log::info!("{}", scene.status());
        let controls = scene.start_controls(size.0, size.1);
        Ok(SceneHost {
            scene,
            descriptor,
            options: options.clone(),
            controls,
            input: Input::default(),
            cursor: None,
            size,
            context: HostContext {
                gl: context.gl.clone(),
                info: context.info.clone(),
                extensions: context.extensions.clone(),
            },
        })
    }

    /// Which scene [`SceneHost::scene`] is.
    pub fn descriptor(&self) -> &'static SceneDescriptor {
        self.descriptor
    }

    /// The scene as its own type, for tests and tools that reach into it; `None` if the host holds
    /// another scene.
    pub fn scene_as<S: Scene>(&mut self) -> Option<&mut S> {
        let scene: &mut dyn Any = &mut *self.scene;
        scene.downcast_mut()
    }

    /// [`SceneHost::scene_as`], shared.
    pub fn scene_as_ref<S: Scene>(&self) -> Option<&S> {
        let scene: &dyn Any = &*self.scene;
        scene.downcast_ref()
    }

    /// Enter: the next scene of [`crate::scenes::SCENES`] with the same options, the camera at its
    /// start. On an error the current scene stays.
    pub fn next_scene(&mut self) -> Result<()> {
        let next = crate::scenes::next(self.descriptor);
        self.switch_scene(next)
    }

    /// `next`'s scene with the same options, the camera at its start. On an error the current scene
    /// stays.
    pub fn switch_scene(&mut self, next: &'static SceneDescriptor) -> Result<()> {
        let options = self.options.clone();
        self.install(next, options)
    }

    /// A file dropped on the window: the scene that opens it ([`crate::scenes::open_file`]), built
    /// with it, the camera at its start. On an error the current scene stays.
    pub fn open_file(&mut self, path: &Path) -> Result<()> {
        let mut options = self.options.clone();
        let next = crate::scenes::open_file(path, &mut options)?;
        self.install(next, options)
    }

    /// Builds `next` with `options` first (so that a failure leaves the current scene), then drops
    /// the old scene's GL objects and puts the camera at the new one's start.
    fn install(&mut self, next: &'static SceneDescriptor, options: SceneOptions) -> Result<()> {
        self.scene = (next.build)(&self.context.scene_context(), &options)?;
        self.options = options;
        self.descriptor = next;
        self.reset_camera();
        log::info!("scene {next}: {}", self.scene.status());
        Ok(())
    }

    /// R: the camera back at the scene's start (the tutorial's, or framing the scene's model).
    pub fn reset_camera(&mut self) {
        self.controls = self.scene.start_controls(self.size.0, self.size.1);
        self.input = Input::default();
    }

    /// The frame's size changed: the projection follows it from the next frame.
    pub fn set_size(&mut self, size: (u32, u32)) {
        self.size = size;
        self.controls.set_viewport(size.0, size.1);
    }

    /// A key of the scene's list (letters upper-case): `Ok(false)` if it is none of them. The
    /// scene's status is logged when it was one.
    pub fn scene_key(&mut self, key: char) -> Result<bool> {
        let taken = self.scene.key(key)?;
        if taken {
            log::info!("{}", self.scene.status());
        }
        Ok(taken)
    }

    /// An arrow key went down (`held`) or up.
    pub fn arrow(&mut self, arrow: Arrow, held: bool) {
        let key = match arrow {
            Arrow::Up => &mut self.input.up,
            Arrow::Down => &mut self.input.down,
            Arrow::Left => &mut self.input.left,
            Arrow::Right => &mut self.input.right,
        };
        *key = held;
    }

    /// Mouse motion for the tutorial's mouse look, in pixels (a front end sends it only while the
    /// cursor is grabbed for it).
    pub fn look(&mut self, (dx, dy): (f64, f64)) {
        self.input.mouse_dx += dx;
        self.input.mouse_dy += dy;
    }

    /// Motion sent so far is dropped (the cursor was just grabbed or released).
    pub fn forget_motion(&mut self) {
        self.input.mouse_dx = 0.0;
        self.input.mouse_dy = 0.0;
    }

    /// The mouse wheel turned by `notches` (positive: away from the user).
    pub fn scroll(&mut self, notches: f32) {
        self.scene.scroll(notches);
    }

    /// A left click for a scene that uses the free cursor.
    pub fn click(&mut self) {
        self.scene.click();
    }

    /// Reads the scene's shader files again: on an error the scene keeps the programs it had.
    pub fn reload_shaders(&mut self) -> Result<()> {
        self.scene.reload_shaders()
    }

    /// Moves the camera by this frame's input (none while time is `frozen`, as with `--frames`),
    /// consuming the mouse motion, and gives what the scene draws the frame with.
    pub fn frame_input(&mut self, delta_time: f32, time: f32, frozen: bool) -> FrameInput {
        let input = if frozen { Input::default() } else { self.input };
        self.forget_motion();
        self.controls
            .compute_matrices_from_inputs(&input, if frozen { 0.0 } else { delta_time });
        FrameInput {
            projection: self.controls.projection_matrix(),
            view: self.controls.view_matrix(),
            cursor: self.cursor,
            size: self.size,
            time: if frozen { 0.0 } else { time },
        }
    }

    /// Draws one frame into the bound framebuffer (whose viewport covers `size`), in the scene's
    /// GL state ([`SceneDescriptor::gl_state`]).
    pub fn draw(&mut self, delta_time: f32, time: f32, frozen: bool) -> FrameInput {
        let input = self.frame_input(delta_time, time, frozen);
        self.descriptor.gl_state.apply(&self.context.gl);
        self.scene.draw(&input);
        input
    }
}
