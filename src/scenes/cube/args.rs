//! The cube scene's command-line arguments, which are its options as they are.

use crate::scenes::options::{LightFlags, OwnOptions, SharedArgs};

// The cube's switches, as the command line sets them. (A plain comment: clap would make a doc
// comment on an Args struct the whole program's `about`.)
#[derive(clap::Args, Debug, Clone, Copy, PartialEq)]
#[command(next_help_heading = "Scene cube")]
pub struct CubeOptions {
    /// The article's `flag`, perturbing the normal with the normal map (its flag `--no-normal-map`
    /// is the table's, on key N).
    #[arg(skip = true)]
    pub normal_mapping: bool,
    /// `--light` (world space) and `--light-power` (a factor on the article's light, 1).
    #[arg(skip)]
    pub light: LightFlags,
}

impl Default for CubeOptions {
    /// Normal mapping on: the article's first screenshot.
    fn default() -> Self {
        CubeOptions {
            normal_mapping: true,
            light: LightFlags::default(),
        }
    }
}

impl OwnOptions for CubeOptions {
    fn with_shared(self, shared: &SharedArgs) -> Self {
        let light = LightFlags::of(shared);
        CubeOptions { light, ..self }
    }
}
