//! Photographs as the photo tools read them (`tutorial13 photometric`, `normalmap --from-photo`):
//! decoded by the `image` crate (PNG, JPEG, TGA, BMP; 8 or 16 bits per channel; grey photos as
//! RGB, alpha dropped), and taken as sRGB-encoded, as cameras and phones write them, unless told
//! they are linear already. Colour-management chunks (gAMA, iCCP, EXIF) are not read.
//!
//! Light adds up linearly, so any arithmetic on brightness (Lambert's law, a blur) is done on linear
//! values: sRGB is decoded with its own curve, c ≤ 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4,
//! and luminance is Rec. 709's (sRGB's primaries) 0.2126 R + 0.7152 G + 0.0722 B of linear RGB.

use std::path::Path;

use crate::normalmap::{decode_image, HeightMap};
use crate::{Error, Result};

/// How a photo's stored values relate to light.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Encoding {
    /// sRGB's transfer curve (what cameras write): decoded to linear light before any arithmetic.
    #[default]
    Srgb,
    /// Already proportional to light (a raw converter's linear output, a render).
    Linear,
}

/// Rec. 709 (sRGB) luminance weights, for linear RGB.
pub const LUMINANCE: [f32; 3] = [0.2126, 0.7152, 0.0722];

impl Encoding {
    /// A stored value (0 to 1) as linear light.
    pub fn to_linear(self, c: f32) -> f32 {
        match self {
            Encoding::Linear => c,
            Encoding::Srgb if c <= 0.04045 => c / 12.92,
            Encoding::Srgb => ((c + 0.055) / 1.055).powf(2.4),
        }
    }

    /// Linear light (0 to 1) as the value a file of this encoding stores.
    pub fn from_linear(self, l: f32) -> f32 {
        match self {
            Encoding::Linear => l,
            Encoding::Srgb if l <= 0.003_130_8 => 12.92 * l,
            Encoding::Srgb => 1.055 * l.powf(1.0 / 2.4) - 0.055,
        }
    }

    /// The 255 midpoints between neighbouring 8-bit values, in linear light: linear light `l` is
    /// stored as the number of midpoints at or below it, round(from_linear(l) · 255).
    pub fn midpoints(self) -> Vec<f32> {
        (0..255)
            .map(|c| self.to_linear((c as f32 + 0.5) / 255.0))
            .collect()
    }

    /// Linear light for every stored value of a `bits`-bit channel (8 or 16), indexed by the value.
    pub fn table(self, bits: u32) -> Vec<f32> {
        let top = (1u32 << bits) - 1;
        (0..=top)
            .map(|c| self.to_linear(c as f32 / top as f32))
            .collect()
    }
}

/// A photo's RGB channels as the file stores them: 8 bits, or 16 where the file has more than 8.
#[derive(Debug, Clone, PartialEq)]
pub enum Samples {
    Eight(Vec<u8>),
    Sixteen(Vec<u16>),
}

/// A decoded photo, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Photo {
    pub width: u32,
    pub height: u32,
    /// `width × height` RGB triples.
    pub samples: Samples,
}

impl Photo {
    /// Reads any image the crate decodes (see the module's documentation); errors name `path`.
    pub fn load(path: &Path) -> Result<Photo> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        Ok(Photo::from_image(decode_image(&bytes, path, "a photo")?))
    }

    /// A decoded image as a photo: 8-bit channels stay 8-bit, deeper ones become 16-bit.
    pub fn from_image(image: image::DynamicImage) -> Photo {
        let (width, height) = (image.width(), image.height());
        let colour = image.color();
        let samples = if colour.bytes_per_pixel() > colour.channel_count() {
            Samples::Sixteen(image.into_rgb16().into_raw())
        } else {
            Samples::Eight(image.into_rgb8().into_raw())
        };
        Photo {
            width,
            height,
            samples,
        }
    }

    /// Bits per channel: 8 or 16.
    pub fn bits(&self) -> u32 {
        match self.samples {
            Samples::Eight(_) => 8,
            Samples::Sixteen(_) => 16,
        }
    }

    /// The same photo with 16-bit channels (v × 257, so 255 stays full scale).
    pub fn to_sixteen(self) -> Photo {
        let samples = match self.samples {
            Samples::Eight(v) => {
                Samples::Sixteen(v.into_iter().map(|c| u16::from(c) * 257).collect())
            }
            sixteen => sixteen,
        };
        Photo { samples, ..self }
    }

    /// Each texel's linear luminance (see the module's documentation).
    pub fn luminance(&self, encoding: Encoding) -> Vec<f32> {
        let table = encoding.table(self.bits());
        let of = |rgb: [usize; 3]| (0..3).map(|c| LUMINANCE[c] * table[rgb[c]]).sum();
        match &self.samples {
            Samples::Eight(v) => v
                .chunks_exact(3)
                .map(|t| of([0, 1, 2].map(|c| usize::from(t[c]))))
                .collect(),
            Samples::Sixteen(v) => v
                .chunks_exact(3)
                .map(|t| of([0, 1, 2].map(|c| usize::from(t[c]))))
                .collect(),
        }
    }
}

/// The default of `normalmap --from-photo --radius`, in texels.
pub const DEFAULT_RADIUS: u32 = 16;

/// `normalmap --from-photo`: one photo's guess at its surface's relief, CrazyBump's way. The
/// photo's linear luminance (sRGB assumed), minus a wide blur of it, is taken as height: brighter
/// than its surroundings = raised. The blur is three box blurs of 2·`radius` + 1 texels, close to a
/// Gaussian of standard deviation √(radius·(radius + 1)) ≈ `radius` + ½; it wraps around the edges
/// as the normal map's derivatives do. Subtracting it removes what changes over more than about
/// `radius` texels (uneven lighting, large stains), which a photo cannot tell from relief anyway.
///
/// What this cannot do: it reads brightness, not shape, so a dark stain is a dent, a light one a
/// bump, an engraved letter lit from the front looks like a raised one (both are bright on top and
/// dark on their slopes), and a bump lit from one side comes out as a bump beside it.
pub fn height_from_photo(photo: &Photo, radius: u32) -> HeightMap {
    let (w, h) = (photo.width as usize, photo.height as usize);
    let luminance = photo.luminance(Encoding::Srgb);
    let mut blurred = luminance.clone();
    for _ in 0..3 {
        box_blur(&mut blurred, w, h, radius as usize);
    }
    let values = luminance.iter().zip(&blurred).map(|(l, b)| l - b).collect();
    HeightMap {
        width: photo.width,
        height: photo.height,
        values,
    }
}

/// A box blur of 2·`radius` + 1 texels along the rows, then the columns, wrapping at the edges (a
/// window wider than the picture counts texels more than once, as the wrapped picture repeats).
fn box_blur(values: &mut [f32], w: usize, h: usize, radius: usize) {
    let mut line = Vec::new();
    // Rows, then columns: one line at a time copied out, blurred back in.
    for (count, stride, step, lines) in [(w, 1, w, h), (h, w, 1, w)] {
        for l in 0..lines {
            let start = l * step;
            line.clear();
            line.extend((0..count).map(|i| values[start + i * stride]));
            let at = |i: isize| line[i.rem_euclid(count as isize) as usize];
            let r = radius as isize;
            let mut sum: f64 = (-r..=r).map(|i| f64::from(at(i))).sum();
            let scale = 1.0 / (2 * radius + 1) as f64;
            for i in 0..count as isize {
                values[start + i as usize * stride] = (sum * scale) as f32;
                sum += f64::from(at(i + r + 1)) - f64::from(at(i - r));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if either sRGB curve leaves its linear segment on the wrong side of the knee (stored
    // 0.04045, linear 0.0031308) or if `from_linear` is not `to_linear`'s inverse: near black the
    // power branch gives 1.055 · l^(1/2.4) − 0.055, below 0 at l = 0 where the line gives 0.
    #[test]
    fn the_srgb_curves_are_each_others_inverse_on_both_sides_of_the_knee() {
        let srgb = Encoding::Srgb;
        assert_eq!(srgb.from_linear(0.0), 0.0);
        assert_eq!(srgb.from_linear(0.001), 12.92 * 0.001);
        assert_eq!(srgb.to_linear(0.02), 0.02 / 12.92);
        for i in 0..=1000 {
            let stored = i as f32 / 1000.0;
            let back = srgb.from_linear(srgb.to_linear(stored));
            assert!((back - stored).abs() < 1e-5, "{stored}: {back}");
        }
        assert_eq!(Encoding::Linear.from_linear(0.25), 0.25);
        assert_eq!(Encoding::Linear.to_linear(0.25), 0.25);
    }
}
