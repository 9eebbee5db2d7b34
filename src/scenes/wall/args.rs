//! The wall scene's command-line arguments.

use crate::scenes::scene::{SceneArgs, SharedArgs};

use super::{LightingSpace, WallOptions};

#[derive(clap::Args, Debug, Clone)]
#[command(next_help_heading = "Scene wall")]
pub struct WallArgs {
    /// Light the stone wall in view space, in tangent space, or without its normal map: view,
    /// tangent, none (key S)
    #[arg(long, value_name = "SPACE", default_value = "view")]
    pub space: LightingSpace,
}

impl SceneArgs for WallArgs {
    type Options = WallOptions;

    fn options(&self, _shared: &SharedArgs) -> WallOptions {
        WallOptions { space: self.space }
    }
}
