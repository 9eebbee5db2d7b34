//! The photos and the mask read from their files: decoded on several threads, checked to share one
//! size, and refused before decoding when the set is too large to hold.

use std::path::{Path, PathBuf};

use crate::normalmap::decode_image;
use crate::photometric::photo::Photo;
use crate::{Error, Result};

/// The mask at `path`: a texel is inside where any channel is nonzero. It must be the size of the
/// photos (`first`, read from `first_path`).
pub(super) fn load_mask(path: &Path, first: &Photo, first_path: &Path) -> Result<Vec<bool>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let image = decode_image(&bytes, path, "a mask")?;
    if (image.width(), image.height()) != (first.width, first.height) {
        return Err(Error::Image {
            path: path.to_path_buf(),
            reason: format!(
                "a {}×{} mask, but {} is {}×{}: the mask must be the photos' size",
                image.width(),
                image.height(),
                first_path.display(),
                first.width,
                first.height
            ),
        });
    }
    let rgb = image.into_rgb16();
    Ok(rgb.pixels().map(|p| p.0 != [0; 3]).collect())
}

/// Checks that `count` photos of `width`×`height`, `bytes` per channel, can be held at once:
/// computes their size and asks the allocator for it before anything is decoded (and gives it
/// back), so that a set too large is refused with the figure instead of aborting half-way.
pub fn reserve_for_photos(count: usize, width: u32, height: u32, bytes: usize) -> Result<()> {
    let need = count as u128 * u128::from(width) * u128::from(height) * 3 * bytes as u128;
    let fits = usize::try_from(need)
        .ok()
        .filter(|&n| n <= isize::MAX as usize)
        .is_some_and(|n| Vec::<u8>::new().try_reserve_exact(n).is_ok());
    if !fits {
        return Err(Error::Photometric(format!(
            "{count} photos of {width}×{height} need {need} bytes ({:.1} GiB) to be held at once, \
             more than this machine can allocate: use fewer photos or crop them",
            need as f64 / f64::from(1u32 << 30)
        )));
    }
    Ok(())
}

/// Reads every photo, `threads` at a time (decoding is a third of the command's time); all must
/// be the first one's size, and the first error in the photos' order is the one reported. If any
/// is deeper than 8 bits, all are widened to 16.
pub fn load_photos(paths: &[PathBuf], threads: usize) -> Result<Vec<Photo>> {
    // The first photo's header gives the set's size (if it has none, its load says why).
    // Without the decoder's limits: the header's size is what is checked here.
    let header = image::ImageReader::open(&paths[0])
        .ok()
        .and_then(|r| r.with_guessed_format().ok())
        .and_then(|mut r| {
            r.no_limits();
            image::ImageDecoder::dimensions(&r.into_decoder().ok()?).into()
        });
    if let Some((width, height)) = header {
        // 16 bits per channel: what any photo deeper than 8 makes of all of them.
        reserve_for_photos(paths.len(), width, height, 2)?;
    }
    let per_thread = paths.len().div_ceil(threads.max(1)).max(1);
    let loaded: Vec<Result<Photo>> = std::thread::scope(|scope| {
        let handles: Vec<_> = paths
            .chunks(per_thread)
            .map(|chunk| scope.spawn(|| chunk.iter().map(|p| Photo::load(p)).collect::<Vec<_>>()))
            .collect();
        let joined = handles
            .into_iter()
            .map(|h| h.join().expect("a photo's decoder panicked"));
        joined.flatten().collect()
    });
    let mut photos = Vec::with_capacity(paths.len());
    for (path, photo) in paths.iter().zip(loaded) {
        let photo = photo?;
        if let Some(first) = photos.first().map(|p: &Photo| (p.width, p.height)) {
            if (photo.width, photo.height) != first {
                return Err(Error::Image {
                    path: path.clone(),
                    reason: format!(
                        "{}×{}, but {} is {}×{}: every photo must be the same size (one camera, \
                         not moved)",
                        photo.width,
                        photo.height,
                        paths[0].display(),
                        first.0,
                        first.1
                    ),
                });
            }
        }
        photos.push(photo);
    }
    if photos.iter().any(|p| p.bits() == 16) {
        photos = photos.into_iter().map(Photo::to_sixteen).collect();
    }
    Ok(photos)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a set too large to hold is not refused before anything is decoded, with the bytes it
    // would need named (96 photos of 4 294 967 295² at 16 bits: far past any address space).
    #[test]
    fn a_set_too_large_to_hold_is_refused_with_its_size() {
        let error = reserve_for_photos(96, u32::MAX, u32::MAX, 2).unwrap_err();
        let need = 96u128 * u128::from(u32::MAX).pow(2) * 6;
        assert!(
            error.to_string().contains(&format!("need {need} bytes")),
            "{error}"
        );
        reserve_for_photos(96, 612, 512, 2).unwrap();
    }
}
