//! The wall scene's command-line arguments, which are its options as they are.

use crate::scenes::options::{LightFlags, OwnOptions, SharedArgs};

use super::LightingSpace;

// The wall's switches, as the command line sets them. (A plain comment: clap would make a doc
// comment on an Args struct the whole program's `about`.)
#[derive(clap::Args, Debug, Clone, Copy, Default, PartialEq)]
#[command(next_help_heading = "Scene wall")]
pub struct WallOptions {
    /// Light the stone wall in view space, in tangent space, or without its normal map (key S)
    #[arg(long, value_enum, value_name = "SPACE", default_value_t = LightingSpace::View)]
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
