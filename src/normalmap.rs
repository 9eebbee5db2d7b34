//! Height map → tangent-space normal map: the tutorial's "How to create a normal map", as a tool
//! (`tutorial13 normalmap HEIGHT.png -o normal.bmp`) and as the function the asset generator calls.
//!
//! Heights are 0 (black, low) to 1 (white, high); only their differences matter, so a constant map
//! (50 % grey or any other) is flat. With x to the right and y up the picture, the surface
//! z = strength · h(x, y) (in texels) has the normal normalize(−strength · ∂h/∂x, −strength · ∂h/∂y, 1),
//! which is what "green up" (OpenGL's convention) stores; "green down" (DirectX's) stores −y.
//! Derivatives wrap around the edges, so that a tiling height map gives a tiling normal map.
//! Each component c is stored as round(127.5 · (c + 1)): a flat texel is exactly (128, 128, 255).

use std::path::Path;

use crate::{Error, Result};

/// The largest side [`HeightMap::load`] accepts (as GL's usual largest texture).
pub const MAX_SIDE: u32 = 16384;

/// The derivative filter.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Kernel {
    /// 3×3 Sobel (weights 1 2 1 across the derivative), smooths noise a little.
    #[default]
    Sobel,
    /// 3×3 Scharr (weights 3 10 3): closer to rotation-invariant than Sobel.
    Scharr,
    /// Plain central differences (h[x+1] − h[x−1]) / 2: the sharpest; the project's own assets use it.
    Central,
}

/// Which way the green channel points.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Green {
    /// +y up the picture (OpenGL's convention, the tutorial's).
    #[default]
    Up,
    /// +y down the picture (DirectX's convention).
    Down,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalMapOptions {
    /// Texels of height that the full black-to-white range stands for: larger = bumpier.
    pub strength: f32,
    pub kernel: Kernel,
    pub green: Green,
    /// Store x and y only (blue 0); a reader rebuilds z = sqrt(1 − x² − y²).
    pub two_channel: bool,
}

impl Default for NormalMapOptions {
    fn default() -> Self {
        NormalMapOptions {
            strength: 8.0,
            kernel: Kernel::default(),
            green: Green::default(),
            two_channel: false,
        }
    }
}

/// A grey-scale height field, row 0 at the top of the picture.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    pub width: u32,
    pub height: u32,
    /// `width × height` values, 0 = low, 1 = high.
    pub values: Vec<f32>,
}

impl HeightMap {
    /// Reads any image the crate decodes (PNG, BMP, TGA; 8 or 16 bits; colour is taken as luma).
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        Self::from_bytes(&bytes, path)
    }

    /// [`HeightMap::load`] on bytes already read; `path` names them in errors. Sides above 16384
    /// texels are refused before anything is decoded.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self> {
        let luma = decode_image(bytes, path, "a height map")?.into_luma16();
        let (width, height) = luma.dimensions();
        let values = luma.pixels().map(|p| f32::from(p.0[0]) / 65535.0).collect();
        Ok(HeightMap {
            width,
            height,
            values,
        })
    }

    fn at(&self, col: usize, row: usize) -> f32 {
        self.values[row * self.width as usize + col]
    }
}

/// Decodes any image the `image` crate reads here (PNG, JPEG, BMP by their contents; TGA, which has
/// no signature, by `path`'s extension), refusing sides above
/// [`MAX_SIDE`] before decoding; errors name `path` and say it is not `what` this program reads.
pub fn decode_image(bytes: &[u8], path: &Path, what: &str) -> Result<image::DynamicImage> {
    let bad = |reason: String| Error::Image {
        path: path.to_path_buf(),
        reason,
    };
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| bad(e.to_string()))?;
    // TGA has no signature to guess it by: its extension says it.
    if reader.format().is_none() {
        if let Ok(format) = image::ImageFormat::from_path(path) {
            reader.set_format(format);
        }
    }
    reader.limits(limits);
    if reader.format() == Some(image::ImageFormat::Jpeg) && jpeg_cut_short(bytes) {
        return Err(bad(format!(
            "not {what} this program reads: a JPEG cut short (no end marker after its last scan)"
        )));
    }
    reader.decode().map_err(|e| {
        // One line: some decoders' messages (zune-jpeg's) end in or hold line breaks.
        let reason = e.to_string().trim().replace('\n', "; ");
        bad(format!("not {what} this program reads: {reason}"))
    })
}

/// Whether a JPEG's last scan (its last start-of-scan marker, FF DA) has no end-of-image marker
/// (FF D9) after it: the file was cut short. The decoder would fill the missing rows in silently.
/// Inside a scan an FF byte is always followed by 00 or a restart marker, so neither pair occurs
/// there by chance; an EXIF thumbnail's own markers come before the main image's scan.
fn jpeg_cut_short(bytes: &[u8]) -> bool {
    let last_scan = bytes.windows(2).rposition(|pair| pair == [0xFF, 0xDA]);
    last_scan.is_some_and(|at| !bytes[at..].windows(2).any(|pair| pair == [0xFF, 0xD9]))
}

/// A unit normal's texel: each component c as round(127.5 · (c + 1)), so flat is (128, 128, 255).
pub fn encode_normal(v: [f32; 3]) -> [u8; 3] {
    let encode = |c: f32| round_to_u8(127.5 * (c + 1.0));
    [encode(v[0]), encode(v[1]), encode(v[2])]
}

/// A unit normal as a 16-bit texel: each component from [−1, 1] to [0, 65535], rounded.
pub fn encode_normal16(v: [f32; 3]) -> [u16; 3] {
    v.map(|c| (32767.5 * (c + 1.0)).round().clamp(0.0, 65535.0) as u16)
}

/// `x.round().clamp(0.0, 255.0) as u8`, to the bit, without a call to libm's `roundf` (which x86-64's
/// baseline instruction set makes a function call: a third of photometric stereo's time per texel).
pub fn round_to_u8(x: f32) -> u8 {
    let x = x.clamp(0.0, 255.0);
    let whole = x as u8;
    // Exact: both are below 2²⁴.
    whole + u8::from(x - f32::from(whole) >= 0.5)
}

/// The normal map of `heights`, RGB texels in the same order (row 0 at the top).
pub fn normal_map(heights: &HeightMap, options: NormalMapOptions) -> Vec<[u8; 3]> {
    let (w, h) = (heights.width as usize, heights.height as usize);
    assert_eq!(
        heights.values.len(),
        w * h,
        "height map of the wrong length"
    );
    let mut out = Vec::with_capacity(w * h);
    for row in 0..h {
        // Wrapped neighbours: the texture repeats.
        let (up, down) = ((row + h - 1) % h, (row + 1) % h);
        for col in 0..w {
            let (left, right) = ((col + w - 1) % w, (col + 1) % w);
            let at = |c, r| heights.at(c, r);
            // ∂h/∂x to the right and ∂h/∂y up the picture, in height per texel.
            let (dh_dx, dh_dy) = match options.kernel {
                Kernel::Central => (
                    (at(right, row) - at(left, row)) * 0.5,
                    (at(col, up) - at(col, down)) * 0.5,
                ),
                Kernel::Sobel | Kernel::Scharr => {
                    let (side, middle, sum) = match options.kernel {
                        Kernel::Sobel => (1.0, 2.0, 8.0),
                        _ => (3.0, 10.0, 32.0),
                    };
                    let column = |c| side * at(c, up) + middle * at(c, row) + side * at(c, down);
                    let line = |r| side * at(left, r) + middle * at(col, r) + side * at(right, r);
                    (
                        (column(right) - column(left)) / sum,
                        (line(up) - line(down)) / sum,
                    )
                }
            };
            let y_sign = match options.green {
                Green::Up => 1.0,
                Green::Down => -1.0,
            };
            let v = [
                -dh_dx * options.strength,
                y_sign * -dh_dy * options.strength,
                1.0,
            ];
            let inv_len = 1.0 / (v[0] * v[0] + v[1] * v[1] + 1.0).sqrt();
            let mut texel = encode_normal(v.map(|c| c * inv_len));
            if options.two_channel {
                texel[2] = 0;
            }
            out.push(texel);
        }
    }
    out
}

/// Writes `texels` (`width × height`, row 0 at the top) as a 24-bit BMP (what the tutorial's
/// `loadBMP_custom` reads) or PNG, by `path`'s extension; atomically.
pub fn write_normal_map(path: &Path, texels: &[[u8; 3]], width: u32, height: u32) -> Result<()> {
    let bytes = normal_map_file(path, texels, width, height)?;
    crate::files::write_bytes_atomically(path, &bytes)
}

/// What [`write_normal_map`] writes to `path`, in memory (the browser page's bake saves it).
pub fn normal_map_file(
    path: &Path,
    texels: &[[u8; 3]],
    width: u32,
    height: u32,
) -> Result<Vec<u8>> {
    let image = image::RgbImage::from_raw(width, height, texels.as_flattened().to_vec());
    encoded(
        path,
        image,
        map_format(path)?,
        (texels.len(), width, height),
    )
}

/// Writes 16-bit RGB texels (row 0 at the top) to `path`, a PNG, atomically.
pub fn write_normal_map16(path: &Path, texels: &[[u16; 3]], width: u32, height: u32) -> Result<()> {
    let bytes = normal_map_file16(path, texels, width, height)?;
    crate::files::write_bytes_atomically(path, &bytes)
}

/// What [`write_normal_map16`] writes to `path`, in memory.
pub fn normal_map_file16(
    path: &Path,
    texels: &[[u16; 3]],
    width: u32,
    height: u32,
) -> Result<Vec<u8>> {
    if map_format(path)? != image::ImageFormat::Png {
        return Err(Error::Write {
            path: path.to_path_buf(),
            reason: "16-bit normal maps are written as PNG only: name it .png".into(),
        });
    }
    let flat: Vec<u16> = texels.iter().flatten().copied().collect();
    let image = image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(width, height, flat);
    encoded(
        path,
        image,
        image::ImageFormat::Png,
        (texels.len(), width, height),
    )
}

/// `image` as the bytes of a `format` file; `None`: `count` texels, too few for its size.
fn encoded<P: image::PixelWithColorType>(
    path: &Path,
    image: Option<image::ImageBuffer<P, Vec<P::Subpixel>>>,
    format: image::ImageFormat,
    (count, width, height): (usize, u32, u32),
) -> Result<Vec<u8>>
where
    [P::Subpixel]: image::EncodableLayout,
{
    let bad = |reason: String| Error::Write {
        path: path.to_path_buf(),
        reason,
    };
    let image = image.ok_or_else(|| bad(format!("{count} texels for {width}×{height}")))?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, format)
        .map_err(|e| bad(e.to_string()))?;
    Ok(bytes.into_inner())
}

/// A map's output (`flag`'s file) refused before any input is read: a format [`map_format`] knows,
/// its folder there ([`crate::files::check_output`]), 16 bits only in a PNG.
pub fn check_map_output(flag: &str, path: &Path, sixteen_bit: bool) -> Result<()> {
    let format = crate::files::check_output(flag, path, map_format)?;
    if sixteen_bit && format != image::ImageFormat::Png {
        return Err(Error::Write {
            path: path.to_path_buf(),
            reason: "--depth 16 writes PNG only: name the output .png".into(),
        });
    }
    Ok(())
}

/// The format [`write_normal_map`] writes to `path`: BMP or PNG by its extension, else an error.
pub fn map_format(path: &Path) -> Result<image::ImageFormat> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("bmp") => Ok(image::ImageFormat::Bmp),
        Some("png") => Ok(image::ImageFormat::Png),
        _ => Err(Error::Write {
            path: path.to_path_buf(),
            reason: "name the output .bmp or .png".into(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `image` encoded as `format`, in memory.
    fn encoded(image: &image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
        let mut bytes = std::io::Cursor::new(Vec::new());
        image.write_to(&mut bytes, format).unwrap();
        bytes.into_inner()
    }

    // Fails if 8-bit or 16-bit greys are not read as their fraction of white (0.2 is 51 of 255 and
    // 13107 of 65535), or come out in another order.
    #[test]
    fn heights_are_the_fraction_of_white_at_either_depth() {
        let grey8 = image::GrayImage::from_raw(3, 1, vec![0, 51, 255]).unwrap();
        let grey16 =
            image::ImageBuffer::<image::Luma<u16>, _>::from_raw(3, 1, vec![0, 13107, 65535])
                .unwrap();
        for image in [
            image::DynamicImage::ImageLuma8(grey8),
            image::DynamicImage::ImageLuma16(grey16),
        ] {
            let bytes = encoded(&image, image::ImageFormat::Png);
            let heights = HeightMap::from_bytes(&bytes, Path::new("h.png")).unwrap();
            assert_eq!((heights.width, heights.height), (3, 1));
            assert_eq!(heights.values, [0.0, 0.2, 1.0]);
        }
    }

    // Fails if a JPEG cut short (its end marker gone) decodes (the decoder would fill the rest in
    // grey), if a whole JPEG does not, even with bytes after its end marker (a check that looks
    // for the end marker among the last bytes only), or if the check is applied to another
    // format: a BMP whose texel bytes happen to be a start-of-scan marker (FF DA) with no end
    // marker after them.
    #[test]
    fn only_a_jpeg_cut_short_is_refused() {
        let picture = image::DynamicImage::ImageRgb8(image::RgbImage::from_fn(16, 16, |x, y| {
            image::Rgb([(x * 16) as u8, (y * 16) as u8, 90])
        }));
        let jpeg = encoded(&picture, image::ImageFormat::Jpeg);
        assert!(decode_image(&jpeg, Path::new("whole.jpg"), "a picture").is_ok());
        // Bytes after the end marker (some cameras append their own) are not a cut.
        let trailing = [jpeg.as_slice(), &[0x00, 0x17]].concat();
        assert!(decode_image(&trailing, Path::new("trailing.jpg"), "a picture").is_ok());
        let cut = &jpeg[..jpeg.len() - 2];
        let error = decode_image(cut, Path::new("cut.jpg"), "a picture").unwrap_err();
        assert!(error.to_string().contains("a JPEG cut short"), "{error}");
        // BMP stores B, G, R: this texel's bytes are FF DA 00.
        let texel = image::DynamicImage::ImageRgb8(
            image::RgbImage::from_raw(1, 1, vec![0x00, 0xDA, 0xFF]).unwrap(),
        );
        let bmp = encoded(&texel, image::ImageFormat::Bmp);
        assert!(bmp.windows(2).any(|pair| pair == [0xFF, 0xDA]));
        assert!(decode_image(&bmp, Path::new("texel.bmp"), "a picture").is_ok());
    }

    // Fails if `round_to_u8` is not `round().clamp(0, 255) as u8` to the bit (halves round up, out
    // of range clamps), or if a normal's components are not encoded as round(127.5 (c + 1)) in 8
    // bits and round(32767.5 (c + 1)) in 16.
    #[test]
    fn normals_encode_as_the_rounded_expansion() {
        for i in 0..=2700 {
            let x = i as f32 * 0.1 - 10.0;
            assert_eq!(round_to_u8(x), x.round().clamp(0.0, 255.0) as u8, "{x}");
        }
        for x in [0.5, 1.5, 127.5, 254.5, 254.49998] {
            assert_eq!(round_to_u8(x), x.round() as u8, "{x}");
        }
        assert_eq!(encode_normal([0.0, 0.0, 1.0]), [128, 128, 255]);
        assert_eq!(encode_normal([-1.0, 1.0, -0.6]), [0, 255, 51]);
        assert_eq!(encode_normal16([-1.0, 0.0, 1.0]), [0, 32768, 65535]);
        assert_eq!(encode_normal16([-0.6, 0.6, 2.0]), [13107, 52428, 65535]);
    }

    // Fails if a kernel's weights are not its own: beside a single raised texel, ∂h/∂x is the
    // middle weight over the sum (Sobel 2/8, Scharr 10/32) or half the step (central), so the
    // texel left of it leans by −strength × that (strength 4: 45° for Sobel).
    #[test]
    fn each_kernel_weighs_a_single_bump_its_own_way() {
        let mut values = vec![0.0; 9];
        values[4] = 1.0;
        let heights = HeightMap {
            width: 3,
            height: 3,
            values,
        };
        for (kernel, left_of_bump) in [
            (Kernel::Sobel, [37, 128, 218]),
            (Kernel::Scharr, [28, 128, 207]),
            (Kernel::Central, [13, 128, 185]),
        ] {
            let options = NormalMapOptions {
                strength: 4.0,
                kernel,
                ..NormalMapOptions::default()
            };
            assert_eq!(normal_map(&heights, options)[3], left_of_bump, "{kernel:?}");
        }
    }

    // Fails if an output is not BMP for .bmp and PNG for .png whatever the case, if any other name
    // is accepted, if a texel count that is not width × height is written, or if a 16-bit map is
    // written as anything but PNG; each refusal writes nothing.
    #[test]
    fn maps_are_written_as_their_names_say() {
        assert_eq!(
            map_format(Path::new("n.BMP")).unwrap(),
            image::ImageFormat::Bmp
        );
        assert_eq!(
            map_format(Path::new("n.png")).unwrap(),
            image::ImageFormat::Png
        );
        for refused in ["n.jpg", "n", "n.bmp.txt"] {
            assert!(map_format(Path::new(refused)).is_err(), "{refused}");
        }
        let dir = std::env::temp_dir().join(format!("normalmap-unit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let texels = [[1, 2, 3], [4, 5, 6]];
        for name in ["two.bmp", "two.png"] {
            let path = dir.join(name);
            write_normal_map(&path, &texels, 2, 1).unwrap();
            let back = image::open(&path).unwrap().into_rgb8();
            assert_eq!(back.into_raw(), [1, 2, 3, 4, 5, 6], "{name}");
            assert!(write_normal_map(&dir.join("short.png"), &texels, 3, 1).is_err());
        }
        let wide = [[0, 1000, 65535], [7, 8, 9]];
        let path = dir.join("two16.png");
        write_normal_map16(&path, &wide, 1, 2).unwrap();
        let back = image::open(&path).unwrap().into_rgb16();
        assert_eq!(back.into_raw(), [0, 1000, 65535, 7, 8, 9]);
        assert!(write_normal_map16(&dir.join("two16.bmp"), &wide, 1, 2).is_err());
        assert!(write_normal_map16(&dir.join("short16.png"), &wide, 2, 2).is_err());
        for absent in ["short.png", "two16.bmp", "short16.png"] {
            assert!(!dir.join(absent).exists(), "{absent} was written");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
