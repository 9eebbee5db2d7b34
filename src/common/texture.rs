//! CPU side of the tutorial's `common/texture.cpp`: reading the DDS and BMP files into memory.
//!
//! The tutorial's `loadDDS` and `loadBMP_custom` read a file and upload it to GL in one go. Here the
//! reading half lives on its own ([`read_dds`], [`read_bmp_custom`]) so that it can be tested without a
//! GL context; the upload (named `load_dds` / `load_bmp_custom`, after the C++) builds on these.
//!
//! The semantics are the tutorial's (which formats, how many levels, how big each level is), but
//! every field the original trusts blindly is checked first, so that a bad file gives an
//! [`Error`] naming the file and the reason instead of a crash or a garbage upload.

use std::path::Path;

use glow::HasContext;

use crate::common::Gl;
use crate::{Error, Result};

/// Largest width or height accepted. GL drivers cap textures well below anything larger, and it
/// keeps every size computation far from overflow.
const MAX_SIDE: u32 = 16384;

/// `"DDS "`, the first four bytes of every DDS file.
const DDS_MAGIC: &[u8; 4] = b"DDS ";
/// Magic (4 bytes) plus the DDS_HEADER structure (124 bytes): what the tutorial reads before the data.
const DDS_HEADER_LEN: usize = 128;
/// Offset of `dwMipMapCount` in the file (the tutorial's `header[24]`, after the magic).
const DDS_MIPMAP_COUNT_OFFSET: usize = 28;

/// The three S3TC block formats the tutorial's `loadDDS` knows about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DxtFormat {
    Dxt1,
    Dxt3,
    Dxt5,
}

impl DxtFormat {
    /// Bytes per 4×4 block: 8 for DXT1, 16 otherwise (the tutorial's rule).
    pub fn block_size(self) -> usize {
        match self {
            DxtFormat::Dxt1 => 8,
            DxtFormat::Dxt3 | DxtFormat::Dxt5 => 16,
        }
    }

    /// The internal format the tutorial passes to `glCompressedTexImage2D`.
    ///
    /// DXT1 maps to `GL_COMPRESSED_RGBA_S3TC_DXT1_EXT` (not the RGB variant), as in the tutorial.
    pub fn gl_internal_format(self) -> u32 {
        match self {
            DxtFormat::Dxt1 => 0x83F1,
            DxtFormat::Dxt3 => 0x83F2,
            DxtFormat::Dxt5 => 0x83F3,
        }
    }

    /// The FourCC code that identifies the format in a DDS pixel format block.
    pub fn fourcc(self) -> [u8; 4] {
        match self {
            DxtFormat::Dxt1 => *b"DXT1",
            DxtFormat::Dxt3 => *b"DXT3",
            DxtFormat::Dxt5 => *b"DXT5",
        }
    }

    fn from_fourcc(code: [u8; 4]) -> Option<DxtFormat> {
        [DxtFormat::Dxt1, DxtFormat::Dxt3, DxtFormat::Dxt5]
            .into_iter()
            .find(|f| f.fourcc() == code)
    }
}

/// One mipmap level, ready for `glCompressedTexImage2D`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DdsLevel {
    pub width: u32,
    pub height: u32,
    pub data: Vec<u8>,
}

/// A DXT-compressed texture with every mipmap level the file holds, largest first.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DdsImage {
    pub format: DxtFormat,
    pub width: u32,
    pub height: u32,
    pub levels: Vec<DdsLevel>,
}

impl DdsLevel {
    /// The level's texels decompressed to RGBA8 (rows in the file's order): for a map read into
    /// memory, and for a browser without `WEBGL_compressed_texture_s3tc`.
    pub fn decompress(&self, format: DxtFormat) -> Vec<u8> {
        let format = match format {
            DxtFormat::Dxt1 => texpresso::Format::Bc1,
            DxtFormat::Dxt3 => texpresso::Format::Bc2,
            DxtFormat::Dxt5 => texpresso::Format::Bc3,
        };
        let (width, height) = (self.width as usize, self.height as usize);
        let mut rgba = vec![0; width * height * 4];
        format.decompress(&self.data, width, height, &mut rgba);
        rgba
    }
}

/// Size in bytes of one compressed level, the tutorial's formula `((w+3)/4) * ((h+3)/4) * block`:
/// every started 4×4 block is stored whole.
///
/// Computed in `usize` with saturation so that no `u32` input can overflow (the C++ `w+3` can).
pub fn dxt_level_size(format: DxtFormat, width: u32, height: u32) -> usize {
    let blocks_x = (width as usize).div_ceil(4);
    let blocks_y = (height as usize).div_ceil(4);
    blocks_x
        .saturating_mul(blocks_y)
        .saturating_mul(format.block_size())
}

/// Reads a DDS file the way the tutorial's `loadDDS` does, without the GL upload.
pub fn read_dds(path: &Path) -> Result<DdsImage> {
    read_with(path, read_dds_bytes)
}

/// Reads `path` whole and parses it with `parse` (which names `path` in its errors).
fn read_with<T>(path: &Path, parse: fn(&[u8], &Path) -> Result<T>) -> Result<T> {
    let bytes = crate::files::read(path).map_err(|e| Error::io(path, e))?;
    parse(&bytes, path)
}

/// Parses DDS bytes already in memory; `path` is only used in error messages.
///
/// Accepts DXT1/DXT3/DXT5 only, like the tutorial, and splits the data into levels with the
/// tutorial's size formula, halving each side per level and clamping at 1.
pub fn read_dds_bytes(bytes: &[u8], path: &Path) -> Result<DdsImage> {
    let fail = |reason: String| Error::Dds {
        path: path.to_path_buf(),
        reason,
    };

    // ddsfile reports a short read as an I/O error with no position; checking the fixed-size
    // header ourselves gives a clearer message (and the tutorial's own order: magic, then header).
    check_magic_then_length(bytes, DDS_MAGIC, DDS_HEADER_LEN, "DDS").map_err(fail)?;

    // Header::read rather than Dds::read, which would copy all the level data into its own buffer.
    let header = ddsfile::Header::read(&bytes[4..DDS_HEADER_LEN])
        .map_err(|e| fail(format!("bad header: {e}")))?;

    let format = dxt_format(&header, &bytes[DDS_HEADER_LEN..]).map_err(|name| {
        fail(format!(
            "unsupported format {name}, only DXT1, DXT3 and DXT5 are supported"
        ))
    })?;

    let (width, height) = (header.width, header.height);
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(fail(format!(
            "absurd size {width}x{height} (each side must be 1 to {MAX_SIDE})"
        )));
    }

    // The tutorial reads dwMipMapCount whether or not DDSD_MIPMAPCOUNT is set, so do the same
    // (ddsfile drops the value when the flag is missing).
    let mip_map_count = header.mip_map_count.unwrap_or_else(|| {
        let field = &bytes[DDS_MIPMAP_COUNT_OFFSET..DDS_MIPMAP_COUNT_OFFSET + 4];
        u32::from_le_bytes(field.try_into().expect("4 bytes of a checked header"))
    });
    // Many writers store 0 for "no mipmaps". The tutorial would then upload no level at all (its
    // loop runs mipMapCount times) and leave an empty texture; the base level is always there, so
    // count it.
    let level_count = mip_map_count.max(1);
    // A full chain ends at 1×1: floor(log2(max(w, h))) + 1 levels. More than that cannot be halved.
    let full_chain = width.max(height).ilog2() + 1;
    if level_count > full_chain {
        return Err(fail(format!(
            "{level_count} mipmap levels, but a {width}x{height} texture has at most {full_chain}"
        )));
    }

    // The tutorial sizes its read buffer from dwPitchOrLinearSize (×2 when mipmapped); that field
    // is often wrong or 0 in the wild, so the level sizes are summed instead.
    // Sizes first, so that nothing is allocated from header claims the data cannot back.
    // At most 15 levels of at most 4096² blocks of 16 bytes: no overflow in u64.
    let mut sizes = Vec::with_capacity(level_count as usize);
    let (mut w, mut h) = (width, height);
    for _ in 0..level_count {
        sizes.push((w, h, dxt_level_size(format, w, h)));
        w = (w / 2).max(1);
        h = (h / 2).max(1);
    }
    let needed: u64 = sizes.iter().map(|&(_, _, size)| size as u64).sum();
    let data = &bytes[DDS_HEADER_LEN..];
    if (data.len() as u64) < needed {
        return Err(fail(format!(
            "level data is cut short: {needed} bytes needed for {level_count} level(s), {} present",
            data.len()
        )));
    }

    // Trailing bytes past the last level are ignored, as the tutorial ignores them.
    let mut offset = 0;
    let levels = sizes
        .into_iter()
        .map(|(width, height, size)| {
            let level = DdsLevel {
                width,
                height,
                data: data[offset..offset + size].to_vec(),
            };
            offset += size;
            level
        })
        .collect();

    Ok(DdsImage {
        format,
        width,
        height,
        levels,
    })
}

/// The DXT format of a parsed header, or a printable name of the format it has instead.
///
/// `rest` is everything after the 128-byte header, read only to name the DXGI format of a
/// DX10 file.
fn dxt_format(header: &ddsfile::Header, rest: &[u8]) -> std::result::Result<DxtFormat, String> {
    use ddsfile::{D3DFormat, FourCC, Header10};

    match &header.spf.fourcc {
        Some(FourCC(FourCC::DX10)) => Err(match Header10::read(rest) {
            Ok(h10) => format!("DX10 header with DXGI format {:?}", h10.dxgi_format),
            Err(_) => "DX10 header".to_owned(),
        }),
        Some(FourCC(code)) => {
            DxtFormat::from_fourcc(code.to_le_bytes()).ok_or_else(|| fourcc_name(*code))
        }
        None => Err(match D3DFormat::try_from_pixel_format(&header.spf) {
            Some(d3d) => format!("uncompressed {d3d:?}"),
            None => match header.spf.rgb_bit_count {
                Some(bits) => format!("uncompressed {bits}-bit"),
                None => "with neither a FourCC nor an RGB layout".to_owned(),
            },
        }),
    }
}

/// `FourCC "ATI2"` for printable codes; D3D9 also stores plain numbers (e.g. 113 for
/// A16B16G16R16F) in the same field.
fn fourcc_name(code: u32) -> String {
    let bytes = code.to_le_bytes();
    if bytes.iter().all(|b| b.is_ascii_graphic() || *b == b' ') {
        format!("FourCC \"{}\"", String::from_utf8_lossy(&bytes))
    } else {
        format!("FourCC {code} ({})", quote_bytes(&bytes))
    }
}

/// Bytes as a quoted string with non-printable ones escaped, for magic-number messages.
fn quote_bytes(bytes: &[u8]) -> String {
    format!("\"{}\"", bytes.escape_ascii())
}

/// The loaders' first two checks, in the tutorial's order: the file's magic (where it is long
/// enough to hold one), then room for the whole `kind` header of `header_len` bytes.
fn check_magic_then_length(
    bytes: &[u8],
    magic: &[u8],
    header_len: usize,
    kind: &str,
) -> std::result::Result<(), String> {
    let n = magic.len();
    if bytes.len() >= n && &bytes[..n] != magic {
        return Err(format!(
            "bad magic {}, expected {}",
            quote_bytes(&bytes[..n]),
            quote_bytes(magic)
        ));
    }
    if bytes.len() < header_len {
        return Err(format!(
            "file is {} bytes, shorter than the {header_len}-byte {kind} header",
            bytes.len()
        ));
    }
    Ok(())
}

/// A 24-bit bitmap as the tutorial uploads it: BGR triples, rows tightly packed, bottom row first.
///
/// Bottom row first is BMP's own order and what `glTexImage2D` expects for texture coordinate
/// v = 0 at the first row. `bgr.len() == width * height * 3`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BmpImage {
    pub width: u32,
    pub height: u32,
    pub bgr: Vec<u8>,
}

/// BITMAPFILEHEADER (14 bytes) plus the smallest DIB header accepted (BITMAPINFOHEADER, 40 bytes):
/// the tutorial's 54-byte header.
const BMP_MIN_HEADER_LEN: usize = 54;
/// BITMAPFILEHEADER size; the DIB header starts here.
const BMP_FILE_HEADER_LEN: usize = 14;

/// Reads a BMP file the way the tutorial's `loadBMP_custom` does, without the GL upload.
pub fn read_bmp_custom(path: &Path) -> Result<BmpImage> {
    read_with(path, read_bmp_bytes)
}

/// Parses BMP bytes already in memory; `path` is only used in error messages.
///
/// Like the tutorial, only 24-bit uncompressed (BI_RGB) bitmaps are accepted. Unlike it, the pixel
/// data is taken from the offset the header gives (not assumed to follow a 54-byte header), row
/// padding to 4 bytes is removed, and top-down files (negative height) are flipped, so that the
/// result is always tightly packed and bottom row first. `biSizeImage` is ignored: BI_RGB files may
/// leave it 0, and the real size follows from width, height and padding.
pub fn read_bmp_bytes(bytes: &[u8], path: &Path) -> Result<BmpImage> {
    let fail = |reason: String| Error::Bmp {
        path: path.to_path_buf(),
        reason,
    };

    check_magic_then_length(bytes, b"BM", BMP_MIN_HEADER_LEN, "BMP").map_err(fail)?;

    let u16_at = |at: usize| u16::from_le_bytes([bytes[at], bytes[at + 1]]);
    let u32_at =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let i32_at = |at: usize| u32_at(at) as i32;

    let data_offset = u32_at(0x0A);
    let dib_size = u32_at(0x0E);
    let width = i32_at(0x12);
    let height = i32_at(0x16);
    let planes = u16_at(0x1A);
    let bits_per_pixel = u16_at(0x1C);
    let compression = u32_at(0x1E);

    // BITMAPINFOHEADER and its extensions (V2, V3, V4, V5) share the fields read above; the
    // 12-byte OS/2 core header stores 16-bit sizes at other offsets.
    if ![40, 52, 56, 108, 124].contains(&dib_size) {
        return Err(fail(format!(
            "unsupported DIB header size {dib_size}, expected 40, 52, 56, 108 or 124"
        )));
    }
    let headers_len = BMP_FILE_HEADER_LEN + dib_size as usize;
    if bytes.len() < headers_len {
        return Err(fail(format!(
            "file is {} bytes, shorter than its {headers_len} bytes of headers",
            bytes.len()
        )));
    }
    if planes != 1 {
        return Err(fail(format!("{planes} colour planes, must be 1")));
    }
    if bits_per_pixel != 24 {
        return Err(fail(format!(
            "{bits_per_pixel} bits per pixel, only 24 is supported"
        )));
    }
    if compression != 0 {
        return Err(fail(format!(
            "compression {} ({compression}), only uncompressed BI_RGB (0) is supported",
            compression_name(compression)
        )));
    }

    if width <= 0 {
        return Err(fail(format!("width {width}, must be positive")));
    }
    if height == 0 {
        return Err(fail("height 0, must not be zero".to_owned()));
    }
    // Positive height: rows stored bottom-up (BMP's usual order); negative: top-down.
    let top_down = height < 0;
    let (width, height) = (width.unsigned_abs(), height.unsigned_abs());
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(fail(format!(
            "absurd size {width}x{height} (each side must be at most {MAX_SIDE})"
        )));
    }

    // The tutorial's fallback for a 0 offset is "right after the header".
    let data_offset = match data_offset as usize {
        0 => headers_len,
        offset if offset < headers_len => {
            return Err(fail(format!(
                "pixel data offset {offset} lies inside the {headers_len} bytes of headers"
            )))
        }
        offset if offset > bytes.len() => {
            return Err(fail(format!(
                "pixel data offset {offset} is beyond the end of the {}-byte file",
                bytes.len()
            )))
        }
        offset => offset,
    };

    // Each stored row is padded to a multiple of 4 bytes. Sizes are bounded by MAX_SIDE, but the
    // arithmetic is checked anyway so that a 32-bit target cannot wrap.
    let too_big = || fail(format!("size {width}x{height} overflows"));
    let row_len = (width as usize).checked_mul(3).ok_or_else(too_big)?;
    let stride = row_len.checked_next_multiple_of(4).ok_or_else(too_big)?;
    let needed = stride.checked_mul(height as usize).ok_or_else(too_big)?;
    let present = bytes.len() - data_offset;
    if present < needed {
        return Err(fail(format!(
            "pixel data is cut short: {needed} bytes needed ({height} rows of {stride}), {present} present"
        )));
    }

    let pixels = &bytes[data_offset..data_offset + needed];
    let mut bgr = Vec::with_capacity(row_len * height as usize);
    let rows = pixels.chunks_exact(stride).map(|row| &row[..row_len]);
    if top_down {
        rows.rev().for_each(|row| bgr.extend_from_slice(row));
    } else {
        rows.for_each(|row| bgr.extend_from_slice(row));
    }

    Ok(BmpImage { width, height, bgr })
}

/// The Windows name of a BMP compression code, for error messages.
fn compression_name(code: u32) -> &'static str {
    match code {
        1 => "BI_RLE8",
        2 => "BI_RLE4",
        3 => "BI_BITFIELDS",
        4 => "BI_JPEG",
        5 => "BI_PNG",
        6 => "BI_ALPHABITFIELDS",
        11 => "BI_CMYK",
        12 => "BI_CMYKRLE8",
        13 => "BI_CMYKRLE4",
        _ => "unknown",
    }
}
// ---------------------------------------------------------------------------------------------------
// GL uploads: the tutorial's loadDDS and loadBMP_custom, on the decoded files above.

/// A GL texture name, deleted with the value.
pub struct Texture {
    gl: Gl,
    pub id: glow::Texture,
}

impl Texture {
    /// `glGenTextures` + `glBindTexture(GL_TEXTURE_2D, …)`: a new texture, bound, for an upload.
    pub fn create_bound(gl: &Gl) -> Result<Self> {
        // SAFETY: plain GL calls on the current context; the name is owned from here on.
        unsafe {
            let id = gl.create_texture().map_err(|e| Error::gl("texture", e))?;
            gl.bind_texture(glow::TEXTURE_2D, Some(id));
            Ok(Texture { gl: gl.clone(), id })
        }
    }
}

/// `loadBMP_custom`'s sampling for the bound texture: REPEAT, linear magnification, trilinear
/// minification, and the mipmaps generated from the level uploaded.
pub fn use_bmp_sampling(gl: &Gl) {
    // SAFETY: state calls on the texture bound to TEXTURE_2D of the current context.
    unsafe {
        gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_S, glow::REPEAT as i32);
        gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_T, glow::REPEAT as i32);
        gl.tex_parameter_i32(
            glow::TEXTURE_2D,
            glow::TEXTURE_MAG_FILTER,
            glow::LINEAR as i32,
        );
        gl.tex_parameter_i32(
            glow::TEXTURE_2D,
            glow::TEXTURE_MIN_FILTER,
            glow::LINEAR_MIPMAP_LINEAR as i32,
        );
        gl.generate_mipmap(glow::TEXTURE_2D);
    }
}

impl Drop for Texture {
    fn drop(&mut self) {
        // SAFETY: made by this context, which the shared `Gl` keeps alive.
        unsafe { self.gl.delete_texture(self.id) };
    }
}

/// The extension that provides DXT1/3/5 textures (llvmpipe and every desktop driver have it).
pub const S3TC_EXTENSION: &str = "GL_EXT_texture_compression_s3tc";

/// WebGL2's name for it (Chromium's SwiftShader has it; some phones do not).
pub const WEBGL_S3TC_EXTENSION: &str = "WEBGL_compressed_texture_s3tc";

/// `loadDDS`: reads `path` and uploads every level, compressed.
pub fn load_dds(gl: &Gl, path: &Path) -> Result<Texture> {
    upload_dds(gl, &read_dds(path)?, path)
}

/// Uploads a decoded DDS as the tutorial does: one `glCompressedTexImage2D` per level, no filter
/// parameters (GL's defaults). One addition: `GL_TEXTURE_MAX_LEVEL` is set to the last level, so a
/// file with fewer levels than a full chain is still complete instead of sampling as black; with a
/// full chain, as the tutorial's, that changes nothing.
pub fn upload_dds(gl: &Gl, dds: &DdsImage, path: &Path) -> Result<Texture> {
    let extensions = gl.supported_extensions();
    let s3tc = extensions.contains(S3TC_EXTENSION) || extensions.contains(WEBGL_S3TC_EXTENSION);
    #[cfg(target_arch = "wasm32")]
    if !s3tc {
        return upload_dds_decompressed(gl, dds, path);
    }
    if !s3tc {
        return Err(Error::Dds {
            path: path.to_path_buf(),
            reason: format!("this GL driver lacks {S3TC_EXTENSION}, needed for DXT textures"),
        });
    }
    let texture = Texture::create_bound(gl)?;
    // SAFETY: plain GL calls on the current context; each level's data has the size GL expects for
    // its dimensions and format (checked by `read_dds`).
    unsafe {
        gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
        for (level, data) in dds.levels.iter().enumerate() {
            gl.compressed_tex_image_2d(
                glow::TEXTURE_2D,
                level as i32,
                dds.format.gl_internal_format() as i32,
                data.width as i32,
                data.height as i32,
                0,
                data.data.len() as i32,
                &data.data,
            );
        }
        gl.tex_parameter_i32(
            glow::TEXTURE_2D,
            glow::TEXTURE_MAX_LEVEL,
            dds.levels.len() as i32 - 1,
        );
        Ok(texture)
    }
}

/// [`upload_dds`] where the browser cannot take DXT: every level decompressed on the CPU and uploaded
/// as RGBA8, sampled as the compressed texture would be (GL's defaults, the same levels). Says so in
/// the log (the page's console), a line per file.
#[cfg(target_arch = "wasm32")]
fn upload_dds_decompressed(gl: &Gl, dds: &DdsImage, path: &Path) -> Result<Texture> {
    log::info!(
        "{}: {} decoded on the CPU ({} levels; the browser lacks {WEBGL_S3TC_EXTENSION})",
        path.display(),
        String::from_utf8_lossy(&dds.format.fourcc()),
        dds.levels.len()
    );
    let texture = Texture::create_bound(gl)?;
    // SAFETY: each level's RGBA8 texels, tightly packed, match its dimensions.
    unsafe {
        gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
        for (level, data) in dds.levels.iter().enumerate() {
            let rgba = data.decompress(dds.format);
            gl.tex_image_2d(
                glow::TEXTURE_2D,
                level as i32,
                glow::RGBA8 as i32,
                data.width as i32,
                data.height as i32,
                0,
                glow::RGBA,
                glow::UNSIGNED_BYTE,
                glow::PixelUnpackData::Slice(Some(&rgba)),
            );
        }
        gl.tex_parameter_i32(
            glow::TEXTURE_2D,
            glow::TEXTURE_MAX_LEVEL,
            dds.levels.len() as i32 - 1,
        );
    }
    Ok(texture)
}

/// `loadBMP_custom`: reads `path` and uploads it.
pub fn load_bmp_custom(gl: &Gl, path: &Path) -> Result<Texture> {
    upload_bmp(gl, &read_bmp_custom(path)?)
}

/// Uploads BGR data as GL_RGB with the tutorial's sampling: REPEAT, trilinear, generated mipmaps.
pub fn upload_bmp(gl: &Gl, bmp: &BmpImage) -> Result<Texture> {
    let size = (bmp.width, bmp.height);
    // WebGL2 takes no BGR: the bytes are swapped to RGB first.
    #[cfg(target_arch = "wasm32")]
    return upload_texels(
        gl,
        glow::RGB8,
        size,
        (glow::RGB, glow::UNSIGNED_BYTE),
        &bmp.bgr
            .chunks_exact(3)
            .flat_map(|bgr| [bgr[2], bgr[1], bgr[0]])
            .collect::<Vec<u8>>(),
    );
    #[cfg(not(target_arch = "wasm32"))]
    upload_texels(
        gl,
        glow::RGB,
        size,
        (glow::BGR, glow::UNSIGNED_BYTE),
        &bmp.bgr,
    )
}

/// A new texture of `bytes`: `size` texels of `format_type` (`glTexImage2D`'s format and type),
/// tightly packed, rows in the order given; sampled as `loadBMP_custom`'s are
/// ([`use_bmp_sampling`]).
pub fn upload_texels(
    gl: &Gl,
    internal_format: u32,
    (width, height): (u32, u32),
    (format, kind): (u32, u32),
    bytes: &[u8],
) -> Result<Texture> {
    let texture = Texture::create_bound(gl)?;
    // SAFETY: `bytes` holds width × height tightly packed texels of `format` and `kind`, matching
    // UNPACK_ALIGNMENT 1.
    unsafe {
        gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
        gl.tex_image_2d(
            glow::TEXTURE_2D,
            0,
            internal_format as i32,
            width as i32,
            height as i32,
            0,
            format,
            kind,
            glow::PixelUnpackData::Slice(Some(bytes)),
        );
    }
    use_bmp_sampling(gl);
    Ok(texture)
}
