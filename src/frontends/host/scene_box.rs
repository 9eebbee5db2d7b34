//! Where the scene goes while the tour's pane shows. The panel alone is drawn over the frame and
//! leaves the scene under it as it was; with the pane as well, a 1024-pixel frame kept a strip of
//! 254 pixels between them, and the tutorial's cylinder, which sits right of the frame's centre, was
//! mostly under the pane. So beside the pane the scene is drawn whole into a target of its own, the
//! largest of the frame's aspect that fits between the panel and the pane, and copied there (one to
//! one), centred, on a ground of the panel's grey. The scene is drawn as in a window of the box's
//! size: the projection's aspect, the size it is given and the cursor are the box's (the host's
//! `frame_in`). The box follows the panel a frame late: it is placed before the panel is laid out.

use glam::Vec2;
use glow::HasContext;

use crate::gl::extensions::GlExtensions;
use crate::gl::offscreen::OffscreenTarget;
use crate::gl::Gl;
use crate::Result;

/// Around the box: egui's dark panels' grey, so that the box sits in the panel's frame.
const GROUND: [f32; 4] = [27.0 / 255.0, 27.0 / 255.0, 27.0 / 255.0, 1.0];

/// The scene's rectangle in the frame, in pixels (x right, y down from the top-left).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SceneBox {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl SceneBox {
    /// The largest box of the frame's aspect between the columns `left` and `right` (pixels) of a
    /// frame of `size`, centred there; `None` where no column is free.
    pub fn between(size: (u32, u32), left: f32, right: f32) -> Option<SceneBox> {
        let (frame_width, frame_height) = (size.0 as f64, size.1 as f64);
        let left = (left.ceil() as f64).max(0.0);
        let room = (right.floor() as f64).min(frame_width) - left;
        // The room is at most the frame's width, so the box is at most its height.
        let width = room;
        let height = (width * frame_height / frame_width).floor();
        (width >= 1.0 && height >= 1.0).then(|| SceneBox {
            x: (left + ((room - width) / 2.0).floor()) as u32,
            y: ((frame_height - height) / 2.0).floor() as u32,
            width: width as u32,
            height: height as u32,
        })
    }

    /// The box's size, which the scene draws at.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// A point of the frame (pixels, y down) in the box's pixels.
    pub fn from_frame(&self, at: Vec2) -> Vec2 {
        at - Vec2::new(self.x as f32, self.y as f32)
    }
}

/// The scene's own target while it is drawn in a box, kept from frame to frame.
#[derive(Debug, Default)]
pub struct BoxedScene {
    target: Option<OffscreenTarget>,
}

impl BoxedScene {
    /// Binds a target of `scene_box`'s size for the scene to draw into (made on the first frame
    /// and whenever the box's size changes), with its viewport; returns the framebuffer that was
    /// bound, where [`BoxedScene::show`] puts the scene.
    ///
    /// The target is stored like a window where the driver can ([`OffscreenTarget::with_window_orientation`]):
    /// llvmpipe's rules for which edge pixels a triangle covers follow the storage, and the scene
    /// must be what a window of the box's size shows, to the pixel.
    pub fn bind(
        &mut self,
        gl: &Gl,
        extensions: &GlExtensions,
        scene_box: &SceneBox,
    ) -> Result<Option<glow::Framebuffer>> {
        // SAFETY: a binding query on the current context.
        let destination =
            unsafe { crate::gl::bound_framebuffer(gl, glow::DRAW_FRAMEBUFFER_BINDING) };
        let (width, height) = scene_box.size();
        let fits =
            (self.target.as_ref()).is_some_and(|t| (t.width(), t.height()) == (width, height));
        if !fits {
            // The old one goes first: two frames' worth of storage need not be held at once.
            self.target = None;
            let target =
                OffscreenTarget::with_window_orientation(gl, (width, height), 0, extensions);
            self.target = Some(target?);
        }
        self.target.as_ref().expect("made above").bind();
        Ok(destination)
    }

    /// The scene drawn since [`BoxedScene::bind`] put into `destination` (a frame of `size`) at
    /// `scene_box`, on the ground colour; `destination` is left bound with the frame's viewport.
    pub fn show(
        &self,
        gl: &Gl,
        destination: Option<glow::Framebuffer>,
        size: (u32, u32),
        scene_box: &SceneBox,
    ) {
        let Some(target) = &self.target else { return };
        let (w, h) = (scene_box.width as i32, scene_box.height as i32);
        // GL's rows count from the bottom.
        let (x, y) = (scene_box.x as i32, size.1 as i32 - scene_box.y as i32 - h);
        // SAFETY: binds, a clear and a blit on the current context; the target is alive.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, destination);
            gl.viewport(0, 0, size.0 as i32, size.1 as i32);
            // The scissor test would clip both; the clear leaves the clear colour alone.
            gl.disable(glow::SCISSOR_TEST);
            gl.clear_buffer_f32_slice(glow::COLOR, 0, &GROUND);
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, target.framebuffer());
            let (mask, filter) = (glow::COLOR_BUFFER_BIT, glow::NEAREST);
            gl.blit_framebuffer(0, 0, w, h, x, y, x + w, y + h, mask, filter);
            gl.bind_framebuffer(glow::FRAMEBUFFER, destination);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails if the box between the panel (folded, 120 pixels; or whole, 330) and the pane (440) is
    /// not the whole room's width at the frame's aspect, centred in height, if a frame with no room
    /// gives a box, or if the cursor is not moved into the box's pixels.
    #[test]
    fn the_box_is_the_largest_of_the_frames_aspect() {
        let tutorial = SceneBox::between((1024, 768), 120.0, 584.0).unwrap();
        assert_eq!(
            tutorial,
            SceneBox {
                x: 120,
                y: 210,
                width: 464,
                height: 348
            }
        );
        // The pane and the whole panel in a maximized 1920 × 1080 window: 1150 × 646 at 16:9.
        let wide = SceneBox::between((1920, 1080), 330.0, 1480.0).unwrap();
        assert_eq!(
            (wide.x, wide.y, wide.width, wide.height),
            (330, 217, 1150, 646)
        );
        assert_eq!(SceneBox::between((1024, 768), 600.0, 584.0), None);
        assert_eq!(
            tutorial.from_frame(Vec2::new(130.0, 220.0)),
            Vec2::new(10.0, 10.0)
        );
    }
}
