//! The scene seam: switching scenes at run time (the window's Enter key, `switch_scene` headless)
//! frees every GL object of the scene it leaves, and a scene built again draws the same frame.

use std::num::NonZeroU32;

use glow::HasContext;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::gl::Profile;
use tutorial13::scenes::SceneName;

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
        let before = live_objects(renderer.context.gl());
        assert!(
            before[0] >= 6 && before[1] >= 3,
            "{before:?}: the scene holds no objects?"
        );
        let mut name = renderer.scene_name;
        for _ in 0..3 * SceneName::ALL.len() {
            name = name.next();
            renderer.switch_scene(name).unwrap();
            renderer.render_frames(1).unwrap();
        }
        assert_eq!(renderer.scene_name, SceneName::Cylinder);
        assert_eq!(live_objects(renderer.context.gl()), before, "{profile}");
        assert!(
            renderer.render_frames(1).unwrap() == first,
            "{profile}: frame changed"
        );
    }
}
