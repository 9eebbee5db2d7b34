//! The TBN debug lines' state on the scene: shown or not, the path they are drawn with (immediate
//! mode or the line shader, [`crate::debug::lines`] draws them), their length, and the light they
//! point at.

use glam::Vec3;

use crate::debug::lines::{DebugLines, LineMode};
use crate::Result;

use super::Cylinder;

/// The TBN lines, or the path they are to be drawn with: one place for the line mode, whether the
/// lines are built or not.
pub(super) enum TbnLines {
    /// Not built yet (they are built the first time they are shown, so that a run without them
    /// neither loads their shader nor prints the core-profile notice), or dropped with the
    /// per-pixel frame. `None`: immediate mode where the context has it, else the line shader.
    Wanted(Option<LineMode>),
    /// Boxed: the lines' state is large beside a mode.
    Built(Box<DebugLines>),
}

impl TbnLines {
    pub(super) fn built(&self) -> Option<&DebugLines> {
        match self {
            TbnLines::Built(lines) => Some(lines),
            TbnLines::Wanted(_) => None,
        }
    }

    pub(super) fn built_mut(&mut self) -> Option<&mut DebugLines> {
        match self {
            TbnLines::Built(lines) => Some(lines),
            TbnLines::Wanted(_) => None,
        }
    }

    /// Drops the lines, keeping the path they were drawn with for when they are built again.
    pub(super) fn drop_built(&mut self) {
        if let TbnLines::Built(lines) = self {
            *self = TbnLines::Wanted(Some(lines.mode()));
        }
    }
}

impl Cylinder {
    /// Whether the TBN lines are shown.
    pub fn show_lines(&self) -> bool {
        self.show_lines
    }

    /// Shows or hides the TBN lines, building them (from the current mesh) the first time. With the
    /// per-pixel frame there are no vertex tangents to draw: the switch is kept, nothing is drawn.
    pub fn set_show_lines(&mut self, show: bool) -> Result<()> {
        let has_tangents = self.mesh.source.has_vertex_tangents();
        if let (true, true, TbnLines::Wanted(mode)) = (show, has_tangents, &self.lines) {
            let lines = DebugLines::with_legacy(
                &self.gl,
                self.legacy.clone(),
                &self.tutorial.mesh,
                self.tutorial.light_position_worldspace,
                *mode,
                self.shaders.dir(),
            )?;
            self.lines = TbnLines::Built(Box::new(lines));
            self.set_line_length(self.line_length)?;
        }
        self.show_lines = show;
        Ok(())
    }

    /// Whether the TBN lines are drawn now: switched on (L), and nothing keeps them from being
    /// drawn ([`super::controls::no_lines`]: the compare view, the per-pixel frame).
    pub(super) fn lines_drawn(&self) -> bool {
        self.show_lines && super::controls::no_lines(self).is_none()
    }

    /// The path the lines are drawn with, once they have been shown.
    pub fn line_mode(&self) -> Option<LineMode> {
        self.lines.built().map(DebugLines::mode)
    }

    /// Why immediate mode is not used, if it was wanted and is not.
    pub fn line_notice(&self) -> Option<&str> {
        self.lines.built().and_then(DebugLines::notice)
    }

    /// The path the lines are drawn with (or will be, once shown).
    pub(super) fn shown_line_mode(&self) -> LineMode {
        match &self.lines {
            TbnLines::Built(lines) => lines.mode(),
            TbnLines::Wanted(Some(LineMode::Legacy) | None) if self.legacy.is_ok() => {
                LineMode::Legacy
            }
            TbnLines::Wanted(_) => LineMode::Shader,
        }
    }

    /// Draws the lines with `mode` (immediate mode falls back to the line shader, with a notice,
    /// where the context has none).
    pub fn set_line_mode(&mut self, mode: LineMode) -> Result<()> {
        match &mut self.lines {
            TbnLines::Built(lines) => lines.set_mode(mode).map(|_| ()),
            TbnLines::Wanted(wanted) => {
                *wanted = Some(mode);
                Ok(())
            }
        }
    }

    /// Makes every TBN line `length` long (the tutorial's is [`crate::debug::lines::LINE_LENGTH`]).
    pub fn set_line_length(&mut self, length: f32) -> Result<()> {
        self.line_length = length;
        match self.lines.built_mut() {
            Some(lines) => lines.reshape(self.tutorial.light_position_worldspace, length),
            None => Ok(()),
        }
    }

    /// Moves the light (world space): the lighting's and the debug lines' cross.
    pub(super) fn move_light(&mut self, light_position_worldspace: Vec3) -> Result<()> {
        self.tutorial.light_position_worldspace = light_position_worldspace;
        if let Some(lines) = self.lines.built_mut() {
            let (_, length) = lines.shape();
            lines.reshape(light_position_worldspace, length)?;
        }
        Ok(())
    }
}
