//! The wall scene's options, as the command line sets them (its `--space` is its table's flag).

use crate::scenes::options::{LightFlags, OwnOptions, SharedArgs};

use super::LightingSpace;

// The wall's switches, as the command line sets them. (A plain comment: clap would make a doc
// comment on an Args struct the whole program's `about`.)
#[derive(clap::Args, Debug, Clone, Copy, Default, PartialEq)]
#[command(next_help_heading = "Scene wall")]
pub struct WallOptions {
    /// Where the wall is lit (`--space` is the table's flag of key S, set once the scene is built).
    #[arg(skip)]
    pub space: LightingSpace,
    /// `--light` (world space) and `--light-power` (the light's intensity, the article's 50).
    #[arg(skip)]
    pub light: LightFlags,
}

impl OwnOptions for WallOptions {
    fn with_shared(self, shared: &SharedArgs) -> Self {
        let light = LightFlags::of(shared);
        WallOptions { light, ..self }
    }
}
