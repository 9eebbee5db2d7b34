//! A model's maps, decoded on the CPU into RGBA pictures (row 0 at the top, as every image viewer
//! shows them) ready for a GL upload.
//!
//! PNG, JPEG, TGA and BMP go through the `image` crate's decoders; DDS through the project's reader
//! (`common::texture`), its first level decompressed. Which way up a picture goes to GL depends on
//! how its sampler reads it: the tutorial's fragment shader reads the diffuse and specular maps at
//! `UV` and the normal map at `(UV.x, -UV.y)`. With V as the modelling tool wrote it (a model), the
//! diffuse and specular maps go bottom row first (GL's order: `t = V` is up the picture), the normal
//! map top row first (`t = -V ≡ 1 - V` is then up the picture). With the tutorial's negated V (its
//! cylinder) it is the other way round. Either way each picture is upright on the surface.

use std::path::Path;

use super::MapSource;
use crate::common::texture::read_dds_bytes;
use crate::normalmap::{decode_image, normal_map, HeightMap, NormalMapOptions};
use crate::{Error, Result};

/// Which of a material's three maps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    Diffuse,
    Normal,
    Specular,
}

impl Slot {
    /// What the neutral map of the slot is, for notices.
    fn neutral(self) -> &'static str {
        match self {
            Slot::Diffuse => "white",
            Slot::Normal => "the flat normal (0, 0, 1)",
            Slot::Specular => "specular 0.3 (the tutorial's constant)",
        }
    }
}

/// An RGBA8 picture, row 0 at the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MapImage {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl MapImage {
    /// The rows in the other order (top first ↔ bottom first), swapped in place.
    pub fn flipped(mut self) -> Self {
        let row = self.width as usize * 4;
        let rows = self.height as usize;
        for top in 0..rows / 2 {
            let (upper, lower) = self.rgba.split_at_mut((rows - 1 - top) * row);
            upper[top * row..(top + 1) * row].swap_with_slice(&mut lower[..row]);
        }
        self
    }

    /// Whether every texel has R = G = B: a height map, not a normal map.
    pub fn is_grey(&self) -> bool {
        self.rgba
            .chunks_exact(4)
            .all(|p| p[0] == p[1] && p[1] == p[2])
    }

    /// Scales each texel's normal x and y by `m` (an MTL `-bm`), z kept, then normalizes.
    pub fn scale_normal_xy(&mut self, m: f32) {
        for p in self.rgba.chunks_exact_mut(4) {
            let c = |b: u8| b as f32 / 127.5 - 1.0;
            let n = glam::Vec3::new(c(p[0]) * m, c(p[1]) * m, c(p[2])).normalize_or(glam::Vec3::Z);
            for (byte, v) in p.iter_mut().zip(n.to_array()) {
                *byte = (127.5 * (v + 1.0)).round().clamp(0.0, 255.0) as u8;
            }
        }
    }

    /// The RGBA picture of a normal map (x, y, z as `normalmap` stores them; alpha 255).
    fn from_normals(width: u32, height: u32, texels: &[[u8; 3]]) -> Self {
        let rgba = texels
            .iter()
            .flat_map(|&[r, g, b]| [r, g, b, 255])
            .collect();
        MapImage {
            width,
            height,
            rgba,
        }
    }
}

/// What a map becomes on the GPU.
#[derive(Debug, Clone, PartialEq)]
pub enum MapPixels {
    /// A picture, row 0 at the top.
    Image(MapImage),
    /// One colour: a 1×1 texture.
    Colour([f32; 3]),
    /// The flat normal, exactly (0, 0, 1) after the shader's `2c − 1`.
    FlatNormal,
}

impl MapPixels {
    fn neutral(slot: Slot) -> Self {
        match slot {
            Slot::Normal => MapPixels::FlatNormal,
            Slot::Diffuse | Slot::Specular => MapPixels::Colour([1.0; 3]),
        }
    }
}

/// Decodes `source` for `slot`. A file a material names that is missing or cannot be decoded
/// becomes the neutral map, with a line in `notices`; one named on the command line is an error.
pub fn decode(source: &MapSource, slot: Slot, notices: &mut Vec<String>) -> Result<MapPixels> {
    match source {
        MapSource::Neutral => Ok(MapPixels::neutral(slot)),
        MapSource::Colour(c) => Ok(MapPixels::Colour(*c)),
        MapSource::Height { path, strength } => {
            let heights = HeightMap::load(path)?;
            Ok(MapPixels::Image(height_to_normals(&heights, *strength)))
        }
        MapSource::File {
            path,
            named_by,
            from_command_line,
            bump_multiplier,
        } => {
            let image = match read_image(path) {
                Ok(image) => image,
                Err(e) if !from_command_line => {
                    notices.push(format!("{named_by}: {e}; using {}", slot.neutral()));
                    return Ok(MapPixels::neutral(slot));
                }
                Err(e) => return Err(e),
            };
            let scale = (*bump_multiplier, "-bm");
            Ok(decoded(image, slot, path, named_by, scale, notices))
        }
        MapSource::Bytes {
            bytes,
            path,
            named_by,
            bump_multiplier,
        } => {
            // The picture's error names the model too: the picture may be one of its buffers.
            let image = read_image_bytes(bytes, path).map_err(|e| match e {
                Error::Image { path, reason } => Error::Image {
                    path,
                    reason: format!("{reason} ({named_by})"),
                },
                e => e,
            })?;
            let scale = (*bump_multiplier, "scale");
            Ok(decoded(image, slot, path, named_by, scale, notices))
        }
    }
}

/// A decoded picture for `slot`: a grey normal map read as heights, `-bm` (or a glTF normal
/// texture's scale) applied; `scale` is that multiplier and the name it is given in notices.
fn decoded(
    image: MapImage,
    slot: Slot,
    path: &Path,
    named_by: &str,
    (bump_multiplier, scale_name): (Option<f32>, &str),
    notices: &mut Vec<String>,
) -> MapPixels {
    if slot != Slot::Normal {
        return MapPixels::Image(image);
    }
    let multiplier = bump_multiplier.unwrap_or(1.0);
    if image.is_grey() {
        // A bump map in the old sense (heights): made into a normal map as `normalmap` does.
        let strength = NormalMapOptions::default().strength * multiplier;
        notices.push(format!(
            "{named_by}: {} is grey, so it is read as a height map (normalmap --strength \
             {strength})",
            path.display()
        ));
        let heights = HeightMap {
            width: image.width,
            height: image.height,
            values: image
                .rgba
                .chunks_exact(4)
                .map(|p| p[0] as f32 / 255.0)
                .collect(),
        };
        return MapPixels::Image(height_to_normals(&heights, strength));
    }
    let mut image = image;
    if multiplier != 1.0 {
        image.scale_normal_xy(multiplier);
        notices.push(format!("{named_by}: {scale_name} {multiplier} applied"));
    }
    MapPixels::Image(image)
}

/// `tutorial13 normalmap` with its defaults and `strength`.
fn height_to_normals(heights: &HeightMap, strength: f32) -> MapImage {
    let options = NormalMapOptions {
        strength,
        ..Default::default()
    };
    let texels = normal_map(heights, options);
    MapImage::from_normals(heights.width, heights.height, &texels)
}

/// Decodes an image file into RGBA8, row 0 at the top: DDS (DXT1/3/5, first level) by its
/// extension, anything else by its contents (PNG, JPEG, TGA, BMP).
pub fn read_image(path: &Path) -> Result<MapImage> {
    let bytes = crate::files::read(path).map_err(|e| Error::io(path, e))?;
    read_image_bytes(&bytes, path)
}

/// [`read_image`] on bytes already read; `path` names them (and its extension picks DDS).
pub fn read_image_bytes(bytes: &[u8], path: &Path) -> Result<MapImage> {
    let is_dds = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("dds"));
    if is_dds {
        return read_dds_image(bytes, path);
    }
    let image = decode_image(bytes, path, "a picture (PNG, JPEG, TGA, BMP, DDS)")?.into_rgba8();
    Ok(MapImage {
        width: image.width(),
        height: image.height(),
        rgba: image.into_raw(),
    })
}

/// The first level of a DXT DDS file, decompressed. A DDS is stored top row first, as other
/// pictures are decoded.
fn read_dds_image(bytes: &[u8], path: &Path) -> Result<MapImage> {
    let dds = read_dds_bytes(bytes, path)?;
    let level = &dds.levels[0];
    Ok(MapImage {
        width: level.width,
        height: level.height,
        rgba: level.decompress(dds.format),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(texels: &[[u8; 4]], width: u32) -> MapImage {
        MapImage {
            width,
            height: texels.len() as u32 / width,
            rgba: texels.concat(),
        }
    }

    // Fails if flipping does not swap rows (and only rows).
    #[test]
    fn flipped_swaps_rows() {
        let a = image(&[[1; 4], [2; 4], [3; 4], [4; 4]], 2);
        assert_eq!(
            a.clone().flipped().rgba,
            [[3; 4], [4; 4], [1; 4], [2; 4]].concat()
        );
        assert_eq!(a.clone().flipped().flipped(), a);
    }

    // Fails if -bm does not scale x and y (a flat texel stays flat, a tilted one tilts more).
    #[test]
    fn bump_multiplier_scales_the_slope() {
        let mut a = image(&[[128, 128, 255, 255], [191, 128, 238, 255]], 2);
        a.scale_normal_xy(2.0);
        assert_eq!(&a.rgba[..4], &[128, 128, 255, 255]);
        assert!(a.rgba[4] > 191, "{:?}", a.rgba);
        assert!(image(&[[7, 7, 7, 255]], 1).is_grey());
        assert!(!image(&[[7, 7, 8, 255]], 1).is_grey());
    }

    // Fails if a material's missing file stops the program, or a command line's does not.
    #[test]
    fn missing_files_fall_back_only_for_materials() {
        let file = |from_command_line| MapSource::File {
            path: "/nonexistent/brick.png".into(),
            named_by: "map_Kd of material 'Brick' in a.mtl".into(),
            from_command_line,
            bump_multiplier: None,
        };
        let mut notices = Vec::new();
        let pixels = decode(&file(false), Slot::Normal, &mut notices).unwrap();
        assert_eq!(pixels, MapPixels::FlatNormal);
        assert!(notices[0].contains("/nonexistent/brick.png"), "{notices:?}");
        let e = decode(&file(true), Slot::Diffuse, &mut notices).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/brick.png"), "{e}");
    }

    // Fails if a material's unreadable map does not end its notice with the slot's neutral map,
    // by name: white, the flat normal, or the tutorial's specular 0.3.
    #[test]
    fn fallback_notices_name_the_neutral_map() {
        let source = MapSource::File {
            path: "/nonexistent/brick.png".into(),
            named_by: "map_Kd of material 'Brick' in a.mtl".into(),
            from_command_line: false,
            bump_multiplier: None,
        };
        for (slot, neutral) in [
            (Slot::Diffuse, "; using white"),
            (Slot::Normal, "; using the flat normal (0, 0, 1)"),
            (
                Slot::Specular,
                "; using specular 0.3 (the tutorial's constant)",
            ),
        ] {
            let mut notices = Vec::new();
            decode(&source, slot, &mut notices).unwrap();
            assert_eq!(notices.len(), 1);
            assert!(notices[0].starts_with("map_Kd of material 'Brick' in a.mtl: "));
            assert!(notices[0].ends_with(neutral), "{slot:?}: {}", notices[0]);
        }
    }

    /// A 3×3 grey ramp, brighter to the right and down (levels 0, 60, 120 plus 30 per row).
    fn grey_ramp() -> MapImage {
        let texels: Vec<[u8; 4]> = (0..9)
            .map(|i| {
                let v = (i % 3) as u8 * 60 + (i / 3) as u8 * 30;
                [v, v, v, 255]
            })
            .collect();
        image(&texels, 3)
    }

    // Fails if a diffuse or specular picture is changed at all (grey or not, `-bm` or not): only
    // a normal map is read as heights or scaled.
    #[test]
    fn only_the_normal_slot_is_reinterpreted() {
        for slot in [Slot::Diffuse, Slot::Specular] {
            let mut notices = Vec::new();
            let pixels = decoded(
                grey_ramp(),
                slot,
                Path::new("ramp.png"),
                "map_Kd of material 'Ramp' in a.mtl",
                (Some(2.0), "-bm"),
                &mut notices,
            );
            assert_eq!(pixels, MapPixels::Image(grey_ramp()));
            assert!(notices.is_empty(), "{notices:?}");
        }
    }

    // Fails if a grey normal map is not read as `normalmap` reads a height map: each level over
    // 255 as the height, at the tool's strength (8) times `-bm` (2), so exactly the tool's
    // output at `--strength 16`, which the notice gives.
    #[test]
    fn grey_normal_map_is_the_height_maps_normal_map() {
        let mut notices = Vec::new();
        let pixels = decoded(
            grey_ramp(),
            Slot::Normal,
            Path::new("ramp.png"),
            "bump of material 'Ramp' in a.mtl",
            (Some(2.0), "-bm"),
            &mut notices,
        );
        let heights = HeightMap {
            width: 3,
            height: 3,
            values: grey_ramp()
                .rgba
                .chunks_exact(4)
                .map(|p| p[0] as f32 / 255.0)
                .collect(),
        };
        let options = NormalMapOptions {
            strength: 16.0,
            ..Default::default()
        };
        let expected = MapImage::from_normals(3, 3, &normal_map(&heights, options));
        assert_ne!(expected, grey_ramp());
        assert_eq!(pixels, MapPixels::Image(expected));
        assert_eq!(
            notices,
            ["bump of material 'Ramp' in a.mtl: ramp.png is grey, so it is read as a height map \
              (normalmap --strength 16)"]
        );
    }

    // Fails if `-bm` is not applied to a coloured normal map's x and y with its notice, or is
    // applied (or noticed) at 1. Texel (191, 64, 238) at -bm 2: x and y decode to ±0.498, doubled
    // to ±0.996, with z 0.867 normalized to (0.602, -0.602, 0.524), which encodes to
    // (204, 51, 194); alpha is kept.
    #[test]
    fn bump_multiplier_tilts_a_coloured_normal_map_exactly() {
        let tilted = image(&[[191, 64, 238, 255]], 1);
        let mut notices = Vec::new();
        let pixels = decoded(
            tilted.clone(),
            Slot::Normal,
            Path::new("n.png"),
            "norm of material 'N' in a.mtl",
            (Some(2.0), "-bm"),
            &mut notices,
        );
        assert_eq!(pixels, MapPixels::Image(image(&[[204, 51, 194, 255]], 1)));
        assert_eq!(notices, ["norm of material 'N' in a.mtl: -bm 2 applied"]);
        notices.clear();
        let pixels = decoded(
            tilted.clone(),
            Slot::Normal,
            Path::new("n.png"),
            "norm of material 'N' in a.mtl",
            (Some(1.0), "-bm"),
            &mut notices,
        );
        assert_eq!(pixels, MapPixels::Image(tilted));
        assert!(notices.is_empty(), "{notices:?}");
    }

    // Fails if a row past the first pair is swapped with the wrong one: five rows of one texel,
    // 1 to 5, come back 5 to 1 (the middle row stays).
    #[test]
    fn flipped_reverses_every_row_pair() {
        let rows: Vec<[u8; 4]> = (1..=5).map(|v| [v; 4]).collect();
        let reversed: Vec<[u8; 4]> = (1..=5).rev().map(|v| [v; 4]).collect();
        assert_eq!(image(&rows, 1).flipped(), image(&reversed, 1));
    }
}
