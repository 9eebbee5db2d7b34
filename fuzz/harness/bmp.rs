//! The `bmp` target: the BMP reader.

use std::path::Path;

use tutorial13::common::texture::read_bmp_bytes;

use super::{rejected, Outcome};

/// The `bmp` target's check (see [`Target::Bmp`](super::Target::Bmp)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    match read_bmp_bytes(input, path) {
        Err(e) => rejected(path, e),
        Ok(bmp) => {
            let expected = bmp.width as usize * bmp.height as usize * 3;
            if bmp.width == 0 || bmp.height == 0 || bmp.bgr.len() != expected {
                return Err(format!(
                    "BMP loaded as {}x{} with {} bytes",
                    bmp.width,
                    bmp.height,
                    bmp.bgr.len()
                ));
            }
            Ok(Outcome::Loaded)
        }
    }
}
