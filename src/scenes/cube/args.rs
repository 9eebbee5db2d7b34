//! The cube scene's command-line arguments, which are its options as they are.

use crate::scenes::options::OwnOptions;

// The cube's switches, as the command line sets them. (A plain comment: clap would make a doc
// comment on an Args struct the whole program's `about`.)
#[derive(clap::Args, Debug, Clone, Copy, PartialEq, Eq)]
#[command(next_help_heading = "Scene cube")]
pub struct CubeOptions {
    /// The article's `flag`, perturbing the normal with the normal map: `--no-normal-map` starts with
    /// it off (key N)
    #[arg(long = "no-normal-map", action = clap::ArgAction::SetFalse)]
    pub normal_mapping: bool,
}

impl Default for CubeOptions {
    /// Normal mapping on: the article's first screenshot.
    fn default() -> Self {
        CubeOptions {
            normal_mapping: true,
        }
    }
}

impl OwnOptions for CubeOptions {}
