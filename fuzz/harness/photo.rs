//! The `photo` target: the photo tools' photos.

use std::path::Path;

use glam::Vec3;

use tutorial13::normalmap::decode_image;
use tutorial13::photometric::photo::{height_from_photo, Photo};
use tutorial13::photometric::{recover, PhotometricOptions};

use super::{rejected, Outcome};

/// The `photo` target's check (see [`Target::Photo`](super::Target::Photo)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    match check_photo_bytes(input, path) {
        None => Ok(Outcome::Rejected("larger than the harness decodes".into())),
        Some(Err(e)) => rejected(path, e),
        Some(Ok(photo)) => check_photo(photo).map(|_| Outcome::Loaded),
    }
}

/// Photos that declare more texels than this are not decoded: a few hundred bytes of JPEG can
/// declare 46 million (seconds and a gigabyte per case, the decoder's time, not the tools'), and the
/// mutants of such a file would fill the pool. The tools' code is the same at any size.
const MAX_PHOTO_TEXELS: u64 = 1 << 16;

/// The photo target: `input`'s declared size first, then decoding and the photo tools.
fn check_photo_bytes(input: &[u8], path: &Path) -> Option<Result<Photo, tutorial13::Error>> {
    let reader = image::ImageReader::new(std::io::Cursor::new(input)).with_guessed_format();
    if let Ok((w, h)) = reader
        .map_err(drop)
        .and_then(|r| r.into_dimensions().map_err(drop))
    {
        if u64::from(w) * u64::from(h) > MAX_PHOTO_TEXELS {
            return None;
        }
    }
    Some(decode_image(input, path, "a photo").map(Photo::from_image))
}

/// The photo tools' promises: one height (finite), normal and albedo texel per texel.
fn check_photo(photo: Photo) -> Result<(), String> {
    let texels = photo.width as usize * photo.height as usize;
    let heights = height_from_photo(&photo, 2);
    if heights.values.len() != texels || !heights.values.iter().all(|h| h.is_finite()) {
        return Err(format!(
            "{} heights (finite: {}) for {texels} texels",
            heights.values.len(),
            heights.values.iter().all(|h| h.is_finite())
        ));
    }
    let lights = [(1.0, 0.0, 1.0), (-0.5, 0.8, 1.0), (-0.5, -0.8, 1.0)].map(Vec3::from);
    let options = PhotometricOptions {
        albedo: true,
        ..Default::default()
    };
    let photos = [photo.clone(), photo.clone(), photo];
    let recovered = recover(&photos, &lights, &options).map_err(|e| e.to_string())?;
    let albedo = recovered.albedo.as_ref().map_or(0, Vec::len);
    if recovered.normals.len() != texels || albedo != texels || recovered.unsolved > texels {
        return Err(format!(
            "{} normals, {albedo} albedo texels, {} unsolved for {texels} texels",
            recovered.normals.len(),
            recovered.unsolved
        ));
    }
    Ok(())
}
