//! Uploads of a learner's maps ([`crate::model::maps`]): RGBA pictures with the tutorial's sampling
//! (`loadBMP_custom`'s: repeat, trilinear, generated mipmaps), and the 1×1 textures that stand in for
//! a map a material does not name. (The port of the tutorial's `texture.cpp`, DDS and BMP, is
//! [`crate::common::texture`].)

use crate::common::texture::{upload_texels, Texture};
use crate::common::Gl;
use crate::model::maps::{MapImage, MapPixels};
use crate::Result;

/// Uploads `pixels`; a picture goes bottom row first when `bottom_row_first`, else top row first
/// (see [`crate::model::maps`] for which sampler needs which).
pub fn upload_map(gl: &Gl, pixels: MapPixels, bottom_row_first: bool) -> Result<Texture> {
    match pixels {
        MapPixels::Image(image) if bottom_row_first => upload_rgba(gl, &image.flipped()),
        MapPixels::Image(image) => upload_rgba(gl, &image),
        MapPixels::Colour(colour) => {
            let [r, g, b] = colour.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
            let texel = MapImage {
                width: 1,
                height: 1,
                rgba: vec![r, g, b, 255],
            };
            upload_rgba(gl, &texel)
        }
        MapPixels::FlatNormal => upload_flat_normal(gl),
    }
}

/// An RGBA8 picture, its rows in the order given, sampled as the tutorial's BMP textures are.
pub fn upload_rgba(gl: &Gl, image: &MapImage) -> Result<Texture> {
    let size = (image.width, image.height);
    let format_type = (glow::RGBA, glow::UNSIGNED_BYTE);
    upload_texels(gl, glow::RGBA8, size, format_type, &image.rgba)
}

/// The flat normal as a 1×1 half-float texel (0.5, 0.5, 1): the shader's `2c − 1` gives exactly
/// (0, 0, 1), where 8 bits (128 or 127) would tilt it by 0.4 %.
fn upload_flat_normal(gl: &Gl) -> Result<Texture> {
    let texel: [f32; 3] = [0.5, 0.5, 1.0];
    let bytes = bytemuck::cast_slice(&texel);
    upload_texels(gl, glow::RGB16F, (1, 1), (glow::RGB, glow::FLOAT), bytes)
}
