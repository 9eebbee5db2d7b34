//! The wall scene's command-line arguments, which are its options as they are.

use glam::Vec3;

use crate::scenes::options::{SceneArgs, SharedArgs};

use super::LightingSpace;

// The wall's switches, as the command line sets them. (A plain comment: clap would make a doc
// comment on an Args struct the whole program's `about`.)
#[derive(clap::Args, Debug, Clone, Copy, Default, PartialEq)]
#[command(next_help_heading = "Scene wall")]
pub struct WallOptions {
    /// Light the stone wall in view space, in tangent space, or without its normal map (key S)
    #[arg(long, value_enum, value_name = "SPACE", default_value_t = LightingSpace::View)]
    pub space: LightingSpace,
    /// `--light` (world space); `None` = the article's.
    #[arg(skip)]
    pub light: Option<Vec3>,
    /// `--light-power`, the light's intensity; `None` = the article's 50.
    #[arg(skip)]
    pub light_power: Option<f32>,
}

impl SceneArgs for WallOptions {
    type Options = WallOptions;

    fn options(&self, shared: &SharedArgs) -> std::result::Result<WallOptions, String> {
        Ok(WallOptions {
            light: shared.light,
            light_power: shared.light_power,
            ..*self
        })
    }
}
