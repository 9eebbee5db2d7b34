//! An `--assets` folder that lacks some of a scene's files: each is taken from the crate's own
//! assets/ folder instead, and said once per process.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use crate::{Error, Result};

/// The crate's own assets/ folder, wherever the binary is started from; in the browser, the page's
/// `assets/` (fetched beside index.html).
pub fn crate_assets_dir() -> PathBuf {
    #[cfg(target_arch = "wasm32")]
    return PathBuf::from("assets");
    #[cfg(not(target_arch = "wasm32"))]
    return Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
}

/// Where one scene load's asset files are (see [`find_assets`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AssetFiles<const N: usize> {
    /// Each file: in the `--assets` folder where it is there, else the crate's copy.
    pub paths: [PathBuf; N],
    /// The files the `--assets` folder lacks (their paths in it), whose crate's copies `paths` holds.
    pub missing: Vec<PathBuf>,
}

/// Finds each of `names` in `dir` (the `--assets` folder), else in `crate_dir`. A file in neither is
/// an error naming the one in `dir` (what the user asked for) and saying the crate's is missing too;
/// a file that `dir` has is taken as it is, readable or not (its loader names it if it is broken).
pub fn find_assets<const N: usize>(
    dir: &Path,
    crate_dir: &Path,
    names: [&str; N],
) -> Result<AssetFiles<N>> {
    let mut missing = Vec::new();
    let mut paths = Vec::with_capacity(N);
    for name in names {
        let (asked, own) = (dir.join(name), crate_dir.join(name));
        // `dir` being the crate's folder, its loader says what is wrong with the file.
        if own == asked || crate::files::try_exists(&asked).map_err(|e| Error::io(&asked, e))? {
            paths.push(asked);
        } else if crate::files::is_file(&own) {
            missing.push(asked);
            paths.push(own);
        } else {
            let reason = format!(
                "no such file, and the crate's own {} is missing too (make-assets writes it)",
                own.display()
            );
            let error = io::Error::new(io::ErrorKind::NotFound, reason);
            return Err(Error::io(asked, error));
        }
    }
    let paths = paths.try_into().expect("one path per name");
    Ok(AssetFiles { paths, missing })
}

/// Every file of an `--assets` folder that this process took from the crate's assets/ instead, in
/// the order they were first missed: each is said once (see [`SceneOptions::asset_files`]).
static TAKEN_FROM_CRATE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The files (their paths in an `--assets` folder) taken from the crate's assets/ so far in this
/// process: those the notices have named.
pub fn taken_from_crate() -> Vec<PathBuf> {
    TAKEN_FROM_CRATE
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .clone()
}

/// One notice for a scene load: the files of `missing` (in `dir`) not said before in this process.
pub(crate) fn say_taken_from_crate(dir: &Path, missing: &[PathBuf]) {
    let mut taken = TAKEN_FROM_CRATE
        .lock()
        .unwrap_or_else(PoisonError::into_inner);
    let mut new = Vec::new();
    for path in missing {
        if !taken.contains(path) {
            taken.push(path.clone());
            new.push(path.strip_prefix(dir).unwrap_or(path).display().to_string());
        }
    }
    if !new.is_empty() {
        log::warn!(
            "--assets {} has no {}: using the crate's own from {} (made by make-assets)",
            dir.display(),
            new.join(", "),
            crate_assets_dir().display()
        );
    }
}
