//! Uploads of a learner's maps ([`crate::model::maps`]): RGBA pictures with the tutorial's sampling
//! (`loadBMP_custom`'s: repeat, trilinear, generated mipmaps), and the 1×1 textures that stand in for
//! a map a material does not name.

use glow::HasContext;

use crate::common::texture::{use_bmp_sampling, Texture};
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
    let texture = Texture::create_bound(gl)?;
    // SAFETY: `rgba` holds width × height × 4 tightly packed bytes, matching UNPACK_ALIGNMENT 1.
    unsafe {
        gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
        gl.tex_image_2d(
            glow::TEXTURE_2D,
            0,
            glow::RGBA8 as i32,
            image.width as i32,
            image.height as i32,
            0,
            glow::RGBA,
            glow::UNSIGNED_BYTE,
            glow::PixelUnpackData::Slice(Some(&image.rgba)),
        );
    }
    use_bmp_sampling(gl);
    Ok(texture)
}

/// The flat normal as a 1×1 half-float texel (0.5, 0.5, 1): the shader's `2c − 1` gives exactly
/// (0, 0, 1), where 8 bits (128 or 127) would tilt it by 0.4 %.
fn upload_flat_normal(gl: &Gl) -> Result<Texture> {
    let texel: [f32; 3] = [0.5, 0.5, 1.0];
    let texture = Texture::create_bound(gl)?;
    // SAFETY: three floats for one RGB texel.
    unsafe {
        gl.tex_image_2d(
            glow::TEXTURE_2D,
            0,
            glow::RGB16F as i32,
            1,
            1,
            0,
            glow::RGB,
            glow::FLOAT,
            glow::PixelUnpackData::Slice(Some(bytemuck::cast_slice(&texel))),
        );
    }
    use_bmp_sampling(gl);
    Ok(texture)
}
