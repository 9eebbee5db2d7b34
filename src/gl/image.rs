//! Frames out of GL and into files: pixel read-back (top row first, as image files are) and atomic
//! image writing (through [`crate::files::write_atomically`], so that a crash never leaves half a file).

use std::path::Path;

use glow::HasContext;
use image::codecs::tga::TgaEncoder;

pub use crate::files::write_atomically;
use crate::{Error, Result};

/// Reads `width × height` RGBA8 pixels from the bottom-left of the currently bound READ framebuffer
/// (also used for the window's back buffer), flipped so that row 0 is the top row as in image files.
///
/// The pack state that decides how many bytes GL writes (alignment, row length, skips, pack buffer)
/// is set to tight packing for the read and restored afterwards.
pub fn read_pixels_rgba(gl: &glow::Context, width: u32, height: u32) -> image::RgbaImage {
    let mut image = image::RgbaImage::new(width, height);
    let (Ok(w), Ok(h)) = (i32::try_from(width), i32::try_from(height)) else {
        // No GL framebuffer can be this large; nothing to read.
        return image;
    };
    let stride = width as usize * 4;
    let mut raw = vec![0u8; stride * height as usize];
    if raw.is_empty() {
        return image;
    }
    const PACK_STATE: [u32; 4] = [
        glow::PACK_ALIGNMENT,
        glow::PACK_ROW_LENGTH,
        glow::PACK_SKIP_ROWS,
        glow::PACK_SKIP_PIXELS,
    ];
    // SAFETY: with the pack state below (alignment 1, no row length, no skips, no pack buffer) GL
    // writes exactly width × height × 4 bytes from the start of `raw`, which is that long.
    unsafe {
        let saved = PACK_STATE.map(|p| gl.get_parameter_i32(p));
        let pack_buffer = crate::gl::bound_buffer(gl, glow::PIXEL_PACK_BUFFER_BINDING);
        gl.bind_buffer(glow::PIXEL_PACK_BUFFER, None);
        for (param, value) in PACK_STATE.into_iter().zip([1, 0, 0, 0]) {
            gl.pixel_store_i32(param, value);
        }
        gl.read_pixels(
            0,
            0,
            w,
            h,
            glow::RGBA,
            glow::UNSIGNED_BYTE,
            glow::PixelPackData::Slice(Some(&mut raw)),
        );
        for (param, value) in PACK_STATE.into_iter().zip(saved) {
            gl.pixel_store_i32(param, value);
        }
        gl.bind_buffer(glow::PIXEL_PACK_BUFFER, pack_buffer);
    }
    // GL's row 0 is the bottom one.
    for (dst, src) in image
        .chunks_exact_mut(stride)
        .zip(raw.chunks_exact(stride).rev())
    {
        dst.copy_from_slice(src);
    }
    image
}

/// The formats a screenshot can be written in, chosen by the file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Bmp,
    Tga,
}

impl ImageFormat {
    /// The format `path`'s extension names (case-insensitive), or why it has none this program writes.
    pub fn from_path(path: &Path) -> Result<Self> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("png") => Ok(ImageFormat::Png),
            Some("bmp") => Ok(ImageFormat::Bmp),
            Some("tga") => Ok(ImageFormat::Tga),
            other => Err(Error::Write {
                path: path.to_path_buf(),
                reason: match other {
                    Some("jpg" | "jpeg") => {
                        "JPEG is lossy and not written: name the file .png, .bmp or .tga".into()
                    }
                    Some(ext) => {
                        format!("cannot write .{ext} images: name the file .png, .bmp or .tga")
                    }
                    None => "no extension: name the file .png, .bmp or .tga".into(),
                },
            }),
        }
    }

    fn image_format(self) -> image::ImageFormat {
        match self {
            ImageFormat::Png => image::ImageFormat::Png,
            ImageFormat::Bmp => image::ImageFormat::Bmp,
            ImageFormat::Tga => image::ImageFormat::Tga,
        }
    }
}

/// Writes `image` as a PNG at `path`, atomically (see [`write_atomically`]).
pub fn write_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    write_image(
        path,
        ImageFormat::Png,
        &image::DynamicImage::ImageRgba8(image.clone()),
    )
}

/// Writes a frame as a screenshot in the format `path`'s extension names (PNG, BMP or TGA): RGB, alpha
/// dropped, because a frame on screen is opaque (the tutorial clears with alpha 0, which viewers
/// would show as transparent). Atomic; an unknown extension is refused before anything is written.
pub fn write_screenshot(path: &Path, image: &image::RgbaImage) -> Result<()> {
    let format = ImageFormat::from_path(path)?;
    let rgb = image::DynamicImage::ImageRgba8(image.clone()).into_rgb8();
    write_image(path, format, &image::DynamicImage::ImageRgb8(rgb))
}

fn write_image(path: &Path, format: ImageFormat, image: &image::DynamicImage) -> Result<()> {
    write_atomically(path, |out| {
        let written = match format {
            // Uncompressed: the crate's run-length packets may cross rows, which the TGA spec
            // forbids and some readers (Pillow) refuse.
            ImageFormat::Tga => image.write_with_encoder(TgaEncoder::new(out).disable_rle()),
            _ => image.write_to(out, format.image_format()),
        };
        written.map_err(|e| match e {
            image::ImageError::IoError(e) => Error::io(path, e),
            other => Error::Write {
                path: path.to_path_buf(),
                reason: other.to_string(),
            },
        })
    })
}
