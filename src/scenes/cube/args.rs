//! The cube scene's command-line arguments, which are its options as they are.

use glam::Vec3;

use crate::scenes::options::{SceneArgs, SharedArgs};

// The cube's switches, as the command line sets them. (A plain comment: clap would make a doc
// comment on an Args struct the whole program's `about`.)
#[derive(clap::Args, Debug, Clone, Copy, PartialEq)]
#[command(next_help_heading = "Scene cube")]
pub struct CubeOptions {
    /// The article's `flag`, perturbing the normal with the normal map: `--no-normal-map` starts with
    /// it off (key N)
    #[arg(long = "no-normal-map", action = clap::ArgAction::SetFalse)]
    pub normal_mapping: bool,
    /// `--light` (world space); `None` = the article's.
    #[arg(skip)]
    pub light: Option<Vec3>,
    /// `--light-power`; `None` = the article's 1.
    #[arg(skip)]
    pub light_power: Option<f32>,
}

impl Default for CubeOptions {
    /// Normal mapping on: the article's first screenshot.
    fn default() -> Self {
        CubeOptions {
            normal_mapping: true,
            light: None,
            light_power: None,
        }
    }
}

impl SceneArgs for CubeOptions {
    type Options = CubeOptions;

    fn options(&self, shared: &SharedArgs) -> std::result::Result<CubeOptions, String> {
        Ok(CubeOptions {
            light: shared.light,
            light_power: shared.light_power,
            ..*self
        })
    }
}
