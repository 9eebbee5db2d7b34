//! The TBN debug lines' state on the scene: shown or not, the path they are drawn with (immediate
//! mode or the line shader, [`crate::debug::lines`] draws them), their length, and the light they
//! point at.

use glam::Vec3;

use crate::debug::lines::{DebugLines, LineMode};
use crate::tangents::TangentSource;
use crate::Result;

use super::Cylinder;

impl Cylinder {
    /// Whether the TBN lines are shown.
    pub fn show_lines(&self) -> bool {
        self.show_lines
    }

    /// Shows or hides the TBN lines, building them (from the current mesh) the first time. With the
    /// per-pixel frame there are no vertex tangents to draw: the switch is kept, nothing is drawn.
    pub fn set_show_lines(&mut self, show: bool) -> Result<()> {
        let has_tangents = self.tangent_source != TangentSource::Derivative;
        if show && has_tangents && self.lines.is_none() {
            let lines = DebugLines::with_legacy(
                &self.gl,
                self.legacy.clone(),
                &self.tutorial.mesh,
                self.tutorial.light_position_worldspace,
                self.line_mode,
                self.shader_dir.as_deref(),
            )?;
            self.lines = Some(lines);
            self.set_line_length(self.line_length)?;
        }
        self.show_lines = show;
        Ok(())
    }

    /// The path the lines are drawn with, once they have been shown.
    pub fn line_mode(&self) -> Option<LineMode> {
        self.lines.as_ref().map(DebugLines::mode)
    }

    /// Why immediate mode is not used, if it was wanted and is not.
    pub fn line_notice(&self) -> Option<&str> {
        self.lines.as_ref().and_then(DebugLines::notice)
    }

    /// The path the lines are drawn with (or will be, once shown).
    pub(super) fn shown_line_mode(&self) -> LineMode {
        match self.line_mode().or(self.line_mode) {
            Some(LineMode::Legacy) | None if self.legacy.is_ok() => LineMode::Legacy,
            _ => LineMode::Shader,
        }
    }

    /// Draws the lines with `mode` (immediate mode falls back to the line shader, with a notice,
    /// where the context has none).
    pub fn set_line_mode(&mut self, mode: LineMode) -> Result<()> {
        self.line_mode = Some(mode);
        if let Some(lines) = &mut self.lines {
            lines.set_mode(mode)?;
        }
        Ok(())
    }

    /// Makes every TBN line `length` long (the tutorial's is [`crate::debug::lines::LINE_LENGTH`]).
    pub fn set_line_length(&mut self, length: f32) -> Result<()> {
        self.line_length = length;
        match &mut self.lines {
            Some(lines) => lines.reshape(self.tutorial.light_position_worldspace, length),
            None => Ok(()),
        }
    }

    /// Moves the light (world space): the lighting's and the debug lines' cross.
    pub(super) fn move_light(&mut self, light_position_worldspace: Vec3) -> Result<()> {
        self.tutorial.light_position_worldspace = light_position_worldspace;
        if let Some(lines) = &mut self.lines {
            let (_, length) = lines.shape();
            lines.reshape(light_position_worldspace, length)?;
        }
        Ok(())
    }
}
