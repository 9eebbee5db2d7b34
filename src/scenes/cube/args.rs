//! The cube scene's command-line arguments.

use crate::scenes::scene::{SceneArgs, SharedArgs};

use super::CubeOptions;

#[derive(clap::Args, Debug, Clone)]
#[command(next_help_heading = "Scene cube")]
pub struct CubeArgs {
    /// Start with normal mapping off (the article's flag; key N)
    #[arg(long)]
    pub no_normal_map: bool,
}

impl SceneArgs for CubeArgs {
    type Options = CubeOptions;

    fn options(&self, _shared: &SharedArgs) -> CubeOptions {
        CubeOptions {
            normal_mapping: !self.no_normal_map,
        }
    }
}
