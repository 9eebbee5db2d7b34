//! The sprite scene's command-line arguments.

use crate::normalmap::Green;
use crate::scenes::options::{SceneArgs, SharedArgs};

use super::SpriteOptions;

#[derive(clap::Args, Debug, Clone)]
#[command(next_help_heading = "Scene sprite")]
pub struct SpriteArgs {}

impl SceneArgs for SpriteArgs {
    type Options = SpriteOptions;

    /// `--light` (shared with the cylinder, which reads it as a position in space) must be above
    /// the sprite here.
    fn options(&self, shared: &SharedArgs) -> Result<SpriteOptions, String> {
        let light = shared.light.unwrap_or(SpriteOptions::default().light);
        if light.z <= 0.0 {
            return Err(format!(
                "--light: Z = {} must be above 0 (the light's height over the sprite)",
                light.z
            ));
        }
        Ok(SpriteOptions {
            light,
            flip_green: shared.green == Green::Down,
            // `--independent-falloff` is the table's (key I), set once the sprite is built.
            independent_falloff: false,
        })
    }
}
