//! `tutorial13 make-assets`: every scene's generated files, written into a folder.

use std::path::PathBuf;

use crate::scenes;
use crate::Result;

/// Generate the project's own assets (cylinder, brick textures, normal map) into a folder
#[derive(clap::Args, Debug, Clone, Default)]
pub struct MakeAssetsOptions {
    /// Output folder (created if missing) [default: the crate's assets/, where the program reads
    /// them]
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Replace files that are already there with other contents (e.g. the tutorial's own files);
    /// without it such files are named and nothing is written
    #[arg(long)]
    pub force: bool,
}

/// Makes every scene's files in memory, writes them (see [`crate::assets::make_assets`]) and prints
/// which were created, replaced or left unchanged.
pub fn make_assets(options: &MakeAssetsOptions) -> Result<()> {
    let files = scenes::generate_assets()?;
    // Where the program reads them unless told otherwise, wherever this is run from.
    let out = options
        .out
        .clone()
        .unwrap_or_else(crate::assets::crate_assets_dir);
    let written = crate::assets::make_assets(&out, &files, options.force)?;
    for (what, paths) in [
        ("created", &written.created),
        ("replaced", &written.replaced),
        ("unchanged", &written.unchanged),
    ] {
        if !paths.is_empty() {
            let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
            println!("{what}: {}", names.join(", "));
        }
    }
    Ok(())
}
