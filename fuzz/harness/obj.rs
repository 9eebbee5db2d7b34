//! The `obj` target: the OBJ reader, and what `load_obj` promises of a soup (shared by the
//! targets that read OBJ text).

use std::path::Path;

use tutorial13::common::objloader::TriangleSoup;
use tutorial13::pipeline::obj_parse::load_obj_bytes_threaded;

use super::{rejected, Outcome};

/// The `obj` target's check (see [`Target::Obj`](super::Target::Obj)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    match load_obj_bytes_threaded(input, path) {
        Err(e) => rejected(path, e),
        Ok(soup) => check_soup(&soup).map(|_| Outcome::Loaded),
    }
}

/// What `load_obj` promises: three corners per triangle, every number finite.
pub(super) fn check_soup(soup: &TriangleSoup) -> Result<(), String> {
    let n = soup.vertices.len();
    if n == 0 || n % 3 != 0 || soup.uvs.len() != n || soup.normals.len() != n {
        return Err(format!(
            "soup of {n} positions, {} UVs, {} normals",
            soup.uvs.len(),
            soup.normals.len()
        ));
    }
    let finite = soup.vertices.iter().all(|v| v.is_finite())
        && soup.uvs.iter().all(|v| v.is_finite())
        && soup.normals.iter().all(|v| v.is_finite());
    if !finite {
        return Err("soup holds a non-finite number".into());
    }
    Ok(())
}
