//! The sprite scene's command-line arguments: none of its own, but `--light`, whose X and Y no
//! control holds (the mouse moves them). Its switches' flags (`--green`, `--independent-falloff`)
//! are its table's.

use crate::scenes::flags::{Shared, SharedArgs};
use crate::scenes::options::SceneArgs;

use super::SpriteOptions;

#[derive(clap::Args, Debug, Clone)]
pub struct SpriteArgs {}

impl SceneArgs for SpriteArgs {
    type Options = SpriteOptions;
    const SHARED: &'static [Shared] = &[Shared::Light];

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
        Ok(SpriteOptions { light })
    }
}
