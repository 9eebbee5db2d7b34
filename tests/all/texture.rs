//! Integration tests for `tutorial13::texture`: the tutorial's own DDS and BMP files, small
//! hand-built files (odd sizes, padding, both row orders), and every kind of bad input.

use std::path::Path;

use glow::HasContext;
use tutorial13::common::texture::{
    dxt_level_size, read_bmp_bytes, read_bmp_custom, read_dds, read_dds_bytes, BmpImage, DdsLevel,
    DxtFormat,
};
use tutorial13::Error;

use crate::common;

// ---------------------------------------------------------------------------------------------
// Builders

/// A 128-byte DDS header (magic included) for a FourCC format, with DDSD_MIPMAPCOUNT set.
fn dds_header(fourcc: &[u8; 4], width: u32, height: u32, mip_map_count: u32) -> Vec<u8> {
    let mut h = vec![0u8; 128];
    let mut put = |at: usize, v: u32| h[at..at + 4].copy_from_slice(&v.to_le_bytes());
    put(0, u32::from_le_bytes(*b"DDS "));
    put(4, 124); // dwSize
    put(8, 0x1 | 0x2 | 0x4 | 0x1000 | 0x20000 | 0x80000); // CAPS|HEIGHT|WIDTH|PIXELFORMAT|MIPMAPCOUNT|LINEARSIZE
    put(12, height);
    put(16, width);
    put(28, mip_map_count);
    put(76, 32); // ddspf.dwSize
    put(80, 0x4); // DDPF_FOURCC
    put(84, u32::from_le_bytes(*fourcc));
    put(108, 0x1000 | 0x8 | 0x400000); // TEXTURE|COMPLEX|MIPMAP
    h
}

/// A DDS header plus `data_len` bytes of data, each byte its offset mod 251 (so that levels differ).
fn dds_file(fourcc: &[u8; 4], width: u32, height: u32, mips: u32, data_len: usize) -> Vec<u8> {
    let mut f = dds_header(fourcc, width, height, mips);
    f.extend((0..data_len).map(|i| (i % 251) as u8));
    f
}

/// Sum of the tutorial's level sizes for a chain of `mips` levels.
fn chain_size(format: DxtFormat, mut w: u32, mut h: u32, mips: u32) -> usize {
    let mut total = 0;
    for _ in 0..mips {
        total += dxt_level_size(format, w, h);
        w = (w / 2).max(1);
        h = (h / 2).max(1);
    }
    total
}

/// A 24-bit BI_RGB BMP with a 40-byte BITMAPINFOHEADER. `rgb_top_down` holds the pixels top row
/// first as RGB; rows are stored bottom-up unless `top_down` (negative height), padded to 4 bytes.
fn bmp_24(width: u32, height: u32, rgb_top_down: &[[u8; 3]], top_down: bool) -> Vec<u8> {
    assert_eq!(rgb_top_down.len(), (width * height) as usize);
    let stride = (width as usize * 3).div_ceil(4) * 4;
    let data_len = stride * height as usize;
    let mut f = Vec::with_capacity(54 + data_len);
    f.extend_from_slice(b"BM");
    f.extend_from_slice(&(54 + data_len as u32).to_le_bytes());
    f.extend_from_slice(&[0; 4]);
    f.extend_from_slice(&54u32.to_le_bytes()); // bfOffBits
    f.extend_from_slice(&40u32.to_le_bytes()); // biSize
    f.extend_from_slice(&(width as i32).to_le_bytes());
    let h = if top_down {
        -(height as i32)
    } else {
        height as i32
    };
    f.extend_from_slice(&h.to_le_bytes());
    f.extend_from_slice(&1u16.to_le_bytes()); // planes
    f.extend_from_slice(&24u16.to_le_bytes()); // bpp
    f.extend_from_slice(&0u32.to_le_bytes()); // BI_RGB
    f.extend_from_slice(&(data_len as u32).to_le_bytes());
    f.extend_from_slice(&2835i32.to_le_bytes());
    f.extend_from_slice(&2835i32.to_le_bytes());
    f.extend_from_slice(&[0; 8]); // colours used, important
    assert_eq!(f.len(), 54);
    let rows: Vec<usize> = if top_down {
        (0..height as usize).collect()
    } else {
        (0..height as usize).rev().collect()
    };
    for y in rows {
        for x in 0..width as usize {
            let [r, g, b] = rgb_top_down[y * width as usize + x];
            f.extend_from_slice(&[b, g, r]);
        }
        // Padding bytes are non-zero so that a loader that keeps them is caught.
        let padded_len = f.len() + stride - width as usize * 3;
        f.resize(padded_len, 0xAB);
    }
    f
}

/// Distinct pixel values for a w×h image, top row first.
fn pattern(width: u32, height: u32) -> Vec<[u8; 3]> {
    (0..width * height)
        .map(|i| [(i * 7) as u8, (i * 13 + 1) as u8, (i * 29 + 2) as u8])
        .collect()
}

/// The reference decode: the `image` crate's RGB rows, top row first, turned into tightly packed
/// BGR bottom row first (what `read_bmp_*` promises).
fn image_crate_bgr_bottom_up(bytes: &[u8]) -> BmpImage {
    let img = image::load_from_memory_with_format(bytes, image::ImageFormat::Bmp)
        .expect("image crate decodes the BMP")
        .to_rgb8();
    let (w, h) = img.dimensions();
    let mut bgr = Vec::with_capacity((w * h * 3) as usize);
    for y in (0..h).rev() {
        for x in 0..w {
            let [r, g, b] = img.get_pixel(x, y).0;
            bgr.extend_from_slice(&[b, g, r]);
        }
    }
    BmpImage {
        width: w,
        height: h,
        bgr,
    }
}

fn set_u16(f: &mut [u8], at: usize, v: u16) {
    f[at..at + 2].copy_from_slice(&v.to_le_bytes());
}

fn set_u32(f: &mut [u8], at: usize, v: u32) {
    f[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

/// A reader of in-memory files: `read_dds_bytes` or `read_bmp_bytes`.
type Reader<T> = fn(&[u8], &Path) -> tutorial13::Result<T>;

/// The variant of a reader's error about a file's contents: "Dds" or "Bmp".
fn kind(e: &Error) -> &'static str {
    match e {
        Error::Dds { .. } => "Dds",
        Error::Bmp { .. } => "Bmp",
        _ => "another variant",
    }
}

/// Asserts an error of `expected` kind (see [`kind`]) whose message names `file` and contains
/// `reason`.
#[track_caller]
fn assert_err<T: std::fmt::Debug>(
    result: tutorial13::Result<T>,
    expected: &str,
    file: &str,
    reason: &str,
) {
    match result {
        Err(e) if kind(&e) == expected => {
            let msg = e.to_string();
            assert!(msg.contains(file), "{msg:?} does not name {file}");
            assert!(msg.contains(reason), "{msg:?} does not say {reason:?}");
        }
        other => panic!("expected Error::{expected} about {reason:?}, got {other:?}"),
    }
}

/// Asserts that `bytes`, read as the DDS file `file`, give a `Dds` error naming it and saying
/// `reason`.
#[track_caller]
fn assert_dds_rejects(bytes: &[u8], file: &str, reason: &str) {
    assert_err(read_dds_bytes(bytes, Path::new(file)), "Dds", file, reason);
}

/// Asserts that `bytes`, read as the BMP file `file`, give a `Bmp` error naming it and saying
/// `reason`.
#[track_caller]
fn assert_bmp_rejects(bytes: &[u8], file: &str, reason: &str) {
    assert_err(read_bmp_bytes(bytes, Path::new(file)), "Bmp", file, reason);
}

/// Asserts an `Io` error whose message names `file`; returns it.
#[track_caller]
fn assert_io_err(result: tutorial13::Result<impl std::fmt::Debug>, file: &str) -> Error {
    match result {
        Err(e @ Error::Io { .. }) => {
            assert!(e.to_string().contains(file));
            e
        }
        other => panic!("expected Error::Io, got {other:?}"),
    }
}

/// Fails if `read` does not load `small` (named `name`), loads or panics on any prefix of it, or,
/// where the tutorial's files are here, loads or panics on the tutorial's `original` cut after
/// each of its first `header` + 4096 bytes, at every 9973rd byte after that, or one byte short.
fn assert_every_truncation_is_an_error<T: std::fmt::Debug>(
    test: &str,
    read: Reader<T>,
    (small, name): (&[u8], &str),
    (original, header): (&str, usize),
) {
    assert!(read(small, Path::new(name)).is_ok());
    for len in 0..small.len() {
        assert!(read(&small[..len], Path::new(name)).is_err(), "{len}");
    }

    let Some(dir) = common::original_assets(&format!("{test} (the tutorial's file)")) else {
        return;
    };
    let bytes = std::fs::read(dir.join(original)).unwrap();
    let lengths = (0..=header + 4096).chain((header + 4096..bytes.len()).step_by(9973));
    for len in lengths.chain([bytes.len() - 1]) {
        assert!(read(&bytes[..len], Path::new(original)).is_err(), "{len}");
    }
}

/// Reads `valid` (named `name`) with each byte at `header` set to each of a few garbage values in
/// turn: a panic fails the test, any result passes.
fn read_with_garbage_headers<T>(
    read: Reader<T>,
    valid: &[u8],
    name: &str,
    header: std::ops::Range<usize>,
) {
    for at in header {
        for value in [0x00, 0x01, 0x7f, 0x80, 0xff] {
            let mut bytes = valid.to_vec();
            bytes[at] = value;
            let _ = read(&bytes, Path::new(name));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// DxtFormat and the size formula

// Fails if a block size, GL enum or FourCC differs from the tutorial's constants.
#[test]
fn dxt_format_constants_match_the_tutorial() {
    assert_eq!(DxtFormat::Dxt1.block_size(), 8);
    assert_eq!(DxtFormat::Dxt3.block_size(), 16);
    assert_eq!(DxtFormat::Dxt5.block_size(), 16);
    assert_eq!(DxtFormat::Dxt1.gl_internal_format(), 0x83F1);
    assert_eq!(DxtFormat::Dxt3.gl_internal_format(), 0x83F2);
    assert_eq!(DxtFormat::Dxt5.gl_internal_format(), 0x83F3);
    assert_eq!(&DxtFormat::Dxt1.fourcc(), b"DXT1");
    assert_eq!(&DxtFormat::Dxt3.fourcc(), b"DXT3");
    assert_eq!(&DxtFormat::Dxt5.fourcc(), b"DXT5");
}

// Fails if dxt_level_size stops rounding partial blocks up, or overflows on huge sides.
#[test]
fn dxt_level_size_is_the_tutorial_formula() {
    assert_eq!(dxt_level_size(DxtFormat::Dxt1, 1, 1), 8);
    assert_eq!(dxt_level_size(DxtFormat::Dxt5, 1, 1), 16);
    assert_eq!(dxt_level_size(DxtFormat::Dxt1, 5, 3), 2 * 8);
    assert_eq!(dxt_level_size(DxtFormat::Dxt3, 8, 8), 4 * 16);
    assert_eq!(dxt_level_size(DxtFormat::Dxt3, 1024, 1024), 1_048_576);
    // No panic in debug builds where the C++ `w + 3` would wrap.
    let _ = dxt_level_size(DxtFormat::Dxt5, u32::MAX, u32::MAX);
}

// ---------------------------------------------------------------------------------------------
// The tutorial's DDS files

// Fails if either original texture no longer loads as DXT3 1024² with 11 levels of the tutorial's sizes.
#[test]
fn tutorial_dds_files_load_with_eleven_levels() {
    let Some(original) = common::original_assets("tutorial_dds_files_load_with_eleven_levels")
    else {
        return;
    };
    for name in ["diffuse.DDS", "specular.DDS"] {
        let path = original.join(name);
        let img = read_dds(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(img.format, DxtFormat::Dxt3, "{name}");
        assert_eq!((img.width, img.height), (1024, 1024), "{name}");
        assert_eq!(img.levels.len(), 11, "{name}");
        let mut side = 1024u32;
        for level in &img.levels {
            assert_eq!((level.width, level.height), (side, side), "{name}");
            let expected = (side as usize).div_ceil(4).pow(2) * 16;
            assert_eq!(level.data.len(), expected, "{name} level {side}");
            side = (side / 2).max(1);
        }
        assert_eq!(img.levels[0].data.len(), 1_048_576);
        assert_eq!(img.levels[1].data.len(), 262_144);
        assert_eq!(img.levels[10].data.len(), 16);

        // The levels are consecutive slices of the file, starting right after the header.
        let bytes = std::fs::read(&path).unwrap();
        let mut offset = 128;
        for level in &img.levels {
            assert_eq!(level.data, &bytes[offset..offset + level.data.len()]);
            offset += level.data.len();
        }
        assert_eq!(offset, bytes.len(), "{name} holds exactly 11 levels");
        assert_eq!(read_dds_bytes(&bytes, &path).unwrap(), img);
    }
}

// ---------------------------------------------------------------------------------------------
// Hand-built DDS files

// Fails if non-power-of-two chains are not halved with clamping to 1, or if DXT1/DXT5 sizes are wrong.
#[test]
fn non_power_of_two_dxt1_and_dxt5_chains() {
    // 5x3 → 2x1 → 1x1 (floor(log2 5) + 1 = 3 levels).
    for (format, sizes) in [
        (DxtFormat::Dxt1, [16, 8, 8]),
        (DxtFormat::Dxt5, [32, 16, 16]),
    ] {
        let total: usize = sizes.iter().sum();
        let bytes = dds_file(&format.fourcc(), 5, 3, 3, total);
        let img = read_dds_bytes(&bytes, Path::new("npot.dds")).unwrap();
        assert_eq!(img.format, format);
        assert_eq!((img.width, img.height), (5, 3));
        let dims: Vec<_> = img.levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(dims, [(5, 3), (2, 1), (1, 1)]);
        let lens: Vec<_> = img.levels.iter().map(|l| l.data.len()).collect();
        assert_eq!(lens, sizes);
        let all: Vec<u8> = img.levels.iter().flat_map(|l| l.data.clone()).collect();
        assert_eq!(all, &bytes[128..]);
    }

    // 7x1 → 3x1 → 1x1, and a tall one, 1x6 → 1x3 → 1x1.
    for (w, h, dims) in [
        (7, 1, [(7, 1), (3, 1), (1, 1)]),
        (1, 6, [(1, 6), (1, 3), (1, 1)]),
    ] {
        let total = chain_size(DxtFormat::Dxt1, w, h, 3);
        let img = read_dds_bytes(&dds_file(b"DXT1", w, h, 3, total), Path::new("x.dds")).unwrap();
        let got: Vec<_> = img.levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(got, dims);
    }
}

// Fails if a DXT5 file written by the ddsfile crate (a common writer's layout) does not load.
#[test]
fn dds_written_by_ddsfile_loads() {
    let mut dds = ddsfile::Dds::new_d3d(ddsfile::NewD3dParams {
        height: 12,
        width: 20,
        depth: None,
        format: ddsfile::D3DFormat::DXT5,
        mipmap_levels: Some(5),
        caps2: None,
    })
    .unwrap();
    for (i, b) in dds.data.iter_mut().enumerate() {
        *b = i as u8;
    }
    let mut bytes = Vec::new();
    dds.write(&mut bytes).unwrap();
    let img = read_dds_bytes(&bytes, Path::new("ddsfile.dds")).unwrap();
    assert_eq!(img.format, DxtFormat::Dxt5);
    let dims: Vec<_> = img.levels.iter().map(|l| (l.width, l.height)).collect();
    assert_eq!(dims, [(20, 12), (10, 6), (5, 3), (2, 1), (1, 1)]);
    let all: Vec<u8> = img.levels.iter().flat_map(|l| l.data.clone()).collect();
    assert_eq!(all, dds.data);
}

// Fails if a mipMapCount of 0 does not give the base level, or if the flag-less count is ignored.
#[test]
fn zero_mip_count_means_one_level_and_count_is_read_without_flag() {
    let size = dxt_level_size(DxtFormat::Dxt1, 8, 8);
    let img = read_dds_bytes(&dds_file(b"DXT1", 8, 8, 0, size), Path::new("a.dds")).unwrap();
    assert_eq!(img.levels.len(), 1);
    assert_eq!(img.levels[0].data.len(), size);

    // DDSD_MIPMAPCOUNT cleared: the tutorial reads the field anyway.
    let mut bytes = dds_file(b"DXT1", 8, 8, 4, chain_size(DxtFormat::Dxt1, 8, 8, 4));
    set_u32(&mut bytes, 8, 0x1 | 0x2 | 0x4 | 0x1000);
    let img = read_dds_bytes(&bytes, Path::new("b.dds")).unwrap();
    assert_eq!(img.levels.len(), 4);
}

// Fails if bytes after the last level are rejected instead of ignored.
#[test]
fn dds_trailing_bytes_are_ignored() {
    let size = chain_size(DxtFormat::Dxt3, 16, 16, 5);
    let bytes = dds_file(b"DXT3", 16, 16, 5, size + 100);
    let img = read_dds_bytes(&bytes, Path::new("t.dds")).unwrap();
    let total: usize = img.levels.iter().map(|l| l.data.len()).sum();
    assert_eq!(total, size);
}

// ---------------------------------------------------------------------------------------------
// Bad DDS input

// Fails if a file not starting with "DDS " is not rejected as bad magic.
#[test]
fn dds_wrong_magic() {
    let mut bytes = dds_file(b"DXT1", 4, 4, 1, 8);
    bytes[..4].copy_from_slice(b"BM\0\x01");
    assert_dds_rejects(&bytes, "dir/magic.DDS", "bad magic");
}

// Fails if a file shorter than the 128-byte header is not reported as such.
#[test]
fn dds_truncated_header() {
    let bytes = dds_header(b"DXT1", 4, 4, 1);
    assert_dds_rejects(
        &bytes[..100],
        "short.dds",
        "file is 100 bytes, shorter than the 128-byte DDS header",
    );
}

// Fails if an empty file is not rejected with the header-length reason.
#[test]
fn dds_empty_file() {
    assert_dds_rejects(&[], "empty.dds", "file is 0 bytes");
}

// Fails if a header whose dwSize is not 124 gets past ddsfile's check unreported.
#[test]
fn dds_bad_header_size_field() {
    let mut bytes = dds_file(b"DXT1", 4, 4, 1, 8);
    set_u32(&mut bytes, 4, 99);
    assert_dds_rejects(&bytes, "hsize.dds", "bad header");
}

// Fails if formats other than DXT1/3/5 (ATI2, DXT2, float, uncompressed, DX10) are accepted or not named.
#[test]
fn dds_unsupported_formats_are_named() {
    let ati2 = dds_file(b"ATI2", 4, 4, 1, 16);
    assert_dds_rejects(&ati2, "ati2.dds", "unsupported format FourCC \"ATI2\"");
    let dxt2 = dds_file(b"DXT2", 4, 4, 1, 16);
    assert_dds_rejects(&dxt2, "dxt2.dds", "FourCC \"DXT2\"");
    let float = dds_file(&113u32.to_le_bytes(), 4, 4, 1, 128);
    assert_dds_rejects(&float, "f16.dds", "FourCC 113");

    // Uncompressed A8R8G8B8, as the DirectX texture tool writes it.
    let mut rgba = dds_file(b"\0\0\0\0", 4, 4, 1, 64);
    set_u32(&mut rgba, 80, 0x40 | 0x1); // DDPF_RGB | DDPF_ALPHAPIXELS
    set_u32(&mut rgba, 88, 32);
    set_u32(&mut rgba, 92, 0x00ff_0000);
    set_u32(&mut rgba, 96, 0x0000_ff00);
    set_u32(&mut rgba, 100, 0x0000_00ff);
    set_u32(&mut rgba, 104, 0xff00_0000);
    assert_dds_rejects(
        &rgba,
        "rgba.dds",
        "unsupported format uncompressed A8R8G8B8",
    );

    // A DX10 header, even for BC1 (DXT1's DXGI name): the tutorial does not read DX10 headers.
    for (format, name) in [
        (ddsfile::DxgiFormat::BC7_UNorm, "BC7_UNorm"),
        (ddsfile::DxgiFormat::BC1_UNorm, "BC1_UNorm"),
    ] {
        let dds = ddsfile::Dds::new_dxgi(ddsfile::NewDxgiParams {
            height: 4,
            width: 4,
            depth: None,
            format,
            mipmap_levels: Some(1),
            array_layers: None,
            caps2: None,
            is_cubemap: false,
            resource_dimension: ddsfile::D3D10ResourceDimension::Texture2D,
            alpha_mode: ddsfile::AlphaMode::Unknown,
        })
        .unwrap();
        let mut bytes = Vec::new();
        dds.write(&mut bytes).unwrap();
        assert_dds_rejects(
            &bytes,
            "dx10.dds",
            &format!("DX10 header with DXGI format {name}"),
        );
        // Cut inside the DX10 header: still a named, clean rejection.
        assert_dds_rejects(&bytes[..130], "dx10.dds", "DX10 header");
    }
}

// Fails if zero or huge dimensions are accepted (they would drive huge allocations or empty uploads).
#[test]
fn dds_absurd_sizes() {
    for (w, h) in [(0, 4), (4, 0), (16385, 4), (4, 16385), (u32::MAX, u32::MAX)] {
        assert_dds_rejects(&dds_file(b"DXT5", w, h, 1, 64), "huge.dds", "absurd size");
    }
    // The limit itself is fine as far as size goes (then the data is missing).
    assert_dds_rejects(
        &dds_file(b"DXT1", 16384, 1, 1, 0),
        "edge.dds",
        "cut short: 32768 bytes needed",
    );
}

// Fails if data shorter than the level sizes is accepted, or the message lacks needed/present counts.
#[test]
fn dds_truncated_level_data() {
    let needed = chain_size(DxtFormat::Dxt1, 5, 3, 3);
    assert_eq!(needed, 32);
    let bytes = dds_file(b"DXT1", 5, 3, 3, needed - 1);
    assert_dds_rejects(
        &bytes,
        "cut.dds",
        "level data is cut short: 32 bytes needed for 3 level(s), 31 present",
    );
    // A header promising a 16384² DXT5 with a full chain, and no data: rejected, not allocated.
    let bytes = dds_header(b"DXT5", 16384, 16384, 15);
    assert_dds_rejects(&bytes, "big.dds", "0 present");
}

// Fails if a mip count beyond floor(log2(max(w, h))) + 1 is accepted.
#[test]
fn dds_too_many_mips() {
    let bytes = dds_file(b"DXT1", 5, 3, 4, 1000);
    assert_dds_rejects(
        &bytes,
        "mips.dds",
        "4 mipmap levels, but a 5x3 texture has at most 3",
    );
    let bytes = dds_file(b"DXT3", 1024, 1024, 12, 2_000_000);
    assert_dds_rejects(&bytes, "mips.dds", "at most 11");
    let bytes = dds_file(b"DXT3", 4, 4, u32::MAX, 64);
    assert_dds_rejects(&bytes, "mips.dds", "mipmap levels");
}

// Fails if a missing DDS file is not reported as Error::Io naming the path.
#[test]
fn dds_missing_file_is_io_error() {
    let path = common::scratch("dds-missing").join("no-such-texture.DDS");
    assert_io_err(read_dds(&path), "no-such-texture.DDS");
}

// Fails if any prefix of a valid DDS file loads, or panics, instead of returning an error.
#[test]
fn dds_every_truncation_is_an_error() {
    let small = dds_file(b"DXT5", 5, 3, 3, chain_size(DxtFormat::Dxt5, 5, 3, 3));
    assert_every_truncation_is_an_error(
        "dds_every_truncation_is_an_error",
        read_dds_bytes,
        (&small, "s.dds"),
        ("diffuse.DDS", 128),
    );
}

// Fails if garbage in any header byte can make the DDS reader panic.
#[test]
fn dds_garbage_headers_never_panic() {
    let valid = dds_file(b"DXT1", 8, 8, 4, chain_size(DxtFormat::Dxt1, 8, 8, 4));
    read_with_garbage_headers(read_dds_bytes, &valid, "g.dds", 4..128);
}

// ---------------------------------------------------------------------------------------------
// The tutorial's BMP

// Fails if normal.bmp is not decoded byte-for-byte like the image crate's decode, in BGR bottom-up order.
#[test]
fn tutorial_normal_bmp_matches_image_crate() {
    let Some(original) = common::original_assets("tutorial_normal_bmp_matches_image_crate") else {
        return;
    };
    let path = original.join("normal.bmp");
    let img = read_bmp_custom(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((img.width, img.height), (1024, 1024));
    assert_eq!(img.bgr.len(), 1024 * 1024 * 3);
    let bytes = std::fs::read(&path).unwrap();
    let reference = image_crate_bgr_bottom_up(&bytes);
    assert!(
        img == reference,
        "normal.bmp differs from the image crate's decode"
    );
    // Bottom-up 24-bit with no padding: the data is exactly the file's pixel bytes.
    assert_eq!(img.bgr, &bytes[54..]);
}

// ---------------------------------------------------------------------------------------------
// Hand-built BMPs

// Fails if row padding is kept or misread, or if top-down files are not flipped to bottom-up.
#[test]
fn small_bmps_with_padding_in_both_row_orders() {
    for width in [1, 2, 3, 4, 5, 7] {
        for height in [1, 2, 3] {
            let pixels = pattern(width, height);
            let bottom_up = bmp_24(width, height, &pixels, false);
            let top_down = bmp_24(width, height, &pixels, true);
            let a = read_bmp_bytes(&bottom_up, Path::new("bu.bmp")).unwrap();
            let b = read_bmp_bytes(&top_down, Path::new("td.bmp")).unwrap();
            assert_eq!((a.width, a.height), (width, height));
            assert_eq!(a, b, "{width}x{height}: row orders disagree");

            // Expected from the pattern itself: bottom row first, BGR.
            let mut expected = Vec::new();
            for y in (0..height as usize).rev() {
                for x in 0..width as usize {
                    let [r, g, b] = pixels[y * width as usize + x];
                    expected.extend_from_slice(&[b, g, r]);
                }
            }
            assert_eq!(a.bgr, expected, "{width}x{height}");

            // And from the image crate, for both files.
            assert_eq!(a, image_crate_bgr_bottom_up(&bottom_up), "{width}x{height}");
            assert_eq!(b, image_crate_bgr_bottom_up(&top_down), "{width}x{height}");
        }
    }
}

// Fails if the pixel data offset (a palette gap, a V5 header) is ignored, as the tutorial does.
#[test]
fn bmp_data_offset_and_larger_dib_headers_are_honoured() {
    let pixels = pattern(3, 2);
    let plain = bmp_24(3, 2, &pixels, false);
    let expected = read_bmp_bytes(&plain, Path::new("p.bmp")).unwrap();

    // 20 junk bytes between the header and the pixels.
    let mut gap = plain[..54].to_vec();
    gap.extend_from_slice(&[0x5A; 20]);
    gap.extend_from_slice(&plain[54..]);
    set_u32(&mut gap, 0x0A, 74);
    assert_eq!(
        read_bmp_bytes(&gap, Path::new("gap.bmp")).unwrap(),
        expected
    );

    // A 124-byte BITMAPV5HEADER (zero-filled extension).
    let mut v5 = plain[..54].to_vec();
    v5.extend_from_slice(&[0; 84]);
    v5.extend_from_slice(&plain[54..]);
    set_u32(&mut v5, 0x0A, 138);
    set_u32(&mut v5, 0x0E, 124);
    assert_eq!(read_bmp_bytes(&v5, Path::new("v5.bmp")).unwrap(), expected);

    // Offset 0: the tutorial's fallback, "right after the header".
    let mut zero = plain.clone();
    set_u32(&mut zero, 0x0A, 0);
    assert_eq!(read_bmp_bytes(&zero, Path::new("z.bmp")).unwrap(), expected);
}

// ---------------------------------------------------------------------------------------------
// Bad BMP input

// Fails if a file without the "BM" magic is accepted.
#[test]
fn bmp_wrong_magic() {
    let mut bytes = bmp_24(2, 2, &pattern(2, 2), false);
    bytes[..2].copy_from_slice(b"BA");
    assert_bmp_rejects(&bytes, "magic.bmp", "bad magic \"BA\"");
}

// Fails if 32-bit or 8-bit bitmaps are accepted or the bit depth is not named.
#[test]
fn bmp_wrong_bit_depths() {
    for bpp in [32u16, 8, 16, 1] {
        let mut bytes = bmp_24(2, 2, &pattern(2, 2), false);
        set_u16(&mut bytes, 0x1C, bpp);
        assert_bmp_rejects(
            &bytes,
            "depth.bmp",
            &format!("{bpp} bits per pixel, only 24 is supported"),
        );
    }
}

// Fails if any compression (RLE, bitfields, JPEG, PNG, CMYK) is accepted or not named by its
// Windows name (an unknown code as "unknown").
#[test]
fn bmp_compressed() {
    for (code, name) in [
        (1u32, "BI_RLE8"),
        (2, "BI_RLE4"),
        (3, "BI_BITFIELDS"),
        (4, "BI_JPEG"),
        (5, "BI_PNG"),
        (6, "BI_ALPHABITFIELDS"),
        (11, "BI_CMYK"),
        (12, "BI_CMYKRLE8"),
        (13, "BI_CMYKRLE4"),
        (7, "unknown"),
    ] {
        let mut bytes = bmp_24(2, 2, &pattern(2, 2), false);
        set_u32(&mut bytes, 0x1E, code);
        assert_bmp_rejects(&bytes, "rle.bmp", &format!("compression {name} ({code})"));
    }
}

// Fails if an OS/2 or unknown DIB header size, or planes != 1, is accepted.
#[test]
fn bmp_bad_dib_size_and_planes() {
    let mut bytes = bmp_24(2, 2, &pattern(2, 2), false);
    set_u32(&mut bytes, 0x0E, 12);
    assert_bmp_rejects(&bytes, "os2.bmp", "unsupported DIB header size 12");
    let mut bytes = bmp_24(8, 8, &pattern(8, 8), false);
    set_u32(&mut bytes, 0x0E, 124);
    assert_bmp_rejects(
        &bytes[..100],
        "v5cut.bmp",
        "shorter than its 138 bytes of headers",
    );
    let mut bytes = bmp_24(2, 2, &pattern(2, 2), false);
    set_u16(&mut bytes, 0x1A, 3);
    assert_bmp_rejects(&bytes, "planes.bmp", "3 colour planes");
}

// Fails if missing pixel bytes are accepted, or the message lacks needed/present counts, also
// where a file ends exactly where its pixels would start (not "shorter than its headers", nor an
// offset "beyond the end").
#[test]
fn bmp_truncated_data() {
    // 5 wide: rows of 15 bytes padded to 16, 3 rows = 48 bytes.
    let bytes = bmp_24(5, 3, &pattern(5, 3), false);
    assert_eq!(bytes.len(), 54 + 48);
    assert_bmp_rejects(
        &bytes[..bytes.len() - 10],
        "cut.bmp",
        "pixel data is cut short: 48 bytes needed (3 rows of 16), 38 present",
    );
    // A header claiming 16384² with no pixels: rejected before anything is allocated.
    let mut bytes = bmp_24(1, 1, &pattern(1, 1), false);
    set_u32(&mut bytes, 0x12, 16384);
    set_u32(&mut bytes, 0x16, (-16384i32) as u32);
    assert_bmp_rejects(&bytes, "claims.bmp", "805306368 bytes needed");
    // Headers and nothing after them, with the data said to start there (offset 54) or right
    // after the header (offset 0): the file is whole up to its pixels, which are missing.
    for offset in [54, 0] {
        let mut headers = bmp_24(5, 3, &pattern(5, 3), false)[..54].to_vec();
        set_u32(&mut headers, 0x0A, offset);
        assert_bmp_rejects(
            &headers,
            "headers-only.bmp",
            "pixel data is cut short: 48 bytes needed (3 rows of 16), 0 present",
        );
    }
}

// Fails if a data offset past the end of the file, or inside the headers, is accepted.
#[test]
fn bmp_bad_data_offset() {
    let mut bytes = bmp_24(2, 2, &pattern(2, 2), false);
    set_u32(&mut bytes, 0x0A, 10_000);
    assert_bmp_rejects(
        &bytes,
        "off.bmp",
        "pixel data offset 10000 is beyond the end",
    );
    set_u32(&mut bytes, 0x0A, u32::MAX);
    assert_bmp_rejects(&bytes, "off.bmp", "beyond the end");
    set_u32(&mut bytes, 0x0A, 20);
    assert_bmp_rejects(&bytes, "off.bmp", "lies inside the 54 bytes of headers");
}

// Fails if dimensions over 16384 (either sign of height) are accepted.
#[test]
fn bmp_absurd_dimensions() {
    for (w, h) in [(16385, 1), (1, 16385), (1, -16385), (i32::MAX, i32::MIN)] {
        let mut bytes = bmp_24(1, 1, &pattern(1, 1), false);
        set_u32(&mut bytes, 0x12, w as u32);
        set_u32(&mut bytes, 0x16, h as u32);
        assert_bmp_rejects(&bytes, "huge.bmp", "absurd size");
    }
}

// Fails if zero or negative widths, or a zero height, are accepted.
#[test]
fn bmp_zero_or_negative_size() {
    for (w, h, reason) in [
        (0, 2, "width 0, must be positive"),
        (-3, 2, "width -3, must be positive"),
        (2, 0, "height 0"),
    ] {
        let mut bytes = bmp_24(2, 2, &pattern(2, 2), false);
        set_u32(&mut bytes, 0x12, w as u32);
        set_u32(&mut bytes, 0x16, h as u32);
        assert_bmp_rejects(&bytes, "zero.bmp", reason);
    }
}

// Fails if a missing BMP is not Error::Io, or its message does not name the path.
#[test]
fn bmp_missing_file_is_io_error() {
    let path = common::scratch("bmp-missing").join("no-such-normal.bmp");
    let e = assert_io_err(read_bmp_custom(&path), "no-such-normal.bmp");
    assert_eq!(e.path(), Some(path.as_path()));
}

// Fails if an empty or header-short BMP is not reported with the header-length reason.
#[test]
fn bmp_empty_and_short_header() {
    assert_bmp_rejects(
        &[],
        "empty.bmp",
        "file is 0 bytes, shorter than the 54-byte BMP header",
    );
    let bytes = bmp_24(2, 2, &pattern(2, 2), false);
    assert_bmp_rejects(&bytes[..30], "short.bmp", "file is 30 bytes");
}

// Fails if any prefix of a valid BMP loads, or panics, instead of returning an error.
#[test]
fn bmp_every_truncation_is_an_error() {
    let small = bmp_24(5, 3, &pattern(5, 3), true);
    assert_every_truncation_is_an_error(
        "bmp_every_truncation_is_an_error",
        read_bmp_bytes,
        (&small, "s.bmp"),
        ("normal.bmp", 54),
    );
}

// Fails if garbage in any header byte can make the BMP reader panic.
#[test]
fn bmp_garbage_headers_never_panic() {
    let valid = bmp_24(5, 3, &pattern(5, 3), false);
    read_with_garbage_headers(read_bmp_bytes, &valid, "g.bmp", 0..54);
}

// Fails if a level is not decompressed as its own format (DXT1's colour block alone, DXT3's explicit
// 4-bit alpha, DXT5's interpolated alpha: each read as another gives other alphas), or if its rows
// come out in another order than the file's: row 0 takes colour 0 (pure red in 5:6:5), row 1
// colour 1 (pure blue).
#[test]
fn each_format_decompresses_its_own_block() {
    // Red and blue in 5:6:5 (red first: four-colour mode), then 2-bit indices row by row.
    let colours = [0x00, 0xF8, 0x1F, 0x00, 0x00, 0x55, 0xAA, 0xFF];
    // DXT3: 4 bits a texel, row 0 at 8 (× 17 = 136), row 1 at 15 (255); DXT5: every texel at its
    // first endpoint, 200.
    for (format, alpha, [a0, a1]) in [
        (DxtFormat::Dxt1, vec![], [255, 255]),
        (
            DxtFormat::Dxt3,
            vec![0x88, 0x88, 0xFF, 0xFF, 0, 0, 0, 0],
            [136, 255],
        ),
        (DxtFormat::Dxt5, vec![200, 0, 0, 0, 0, 0, 0, 0], [200, 200]),
    ] {
        let level = DdsLevel {
            width: 4,
            height: 4,
            data: [alpha, colours.to_vec()].concat(),
        };
        let rgba = level.decompress(format);
        assert_eq!(rgba.len(), 4 * 4 * 4, "{format:?}");
        let row = |r: usize| &rgba[16 * r..16 * (r + 1)];
        assert_eq!(row(0), [255, 0, 0, a0].repeat(4), "{format:?} row 0");
        assert_eq!(row(1), [0, 0, 255, a1].repeat(4), "{format:?} row 1");
    }
}

// ---------------------------------------------------------------------------------------------
// The GL uploads (headless, llvmpipe)

/// Level `level`'s value of `parameter` for the bound 2D texture.
fn level_parameter(gl: &tutorial13::common::Gl, level: i32, parameter: u32) -> i32 {
    // SAFETY: a query on the current context's bound texture.
    unsafe { gl.get_tex_level_parameter_i32(glow::TEXTURE_2D, level, parameter) }
}

// Fails if `upload_bmp` loses, reorders or swaps a texel (read back as BGR, the file's order), if
// `loadBMP_custom`'s sampling is not set (REPEAT both ways, linear magnification, trilinear
// minification) or its mipmaps not generated (level 1 is half the size), if `upload_dds` does not
// upload every level with its size, format and byte count, or sets TEXTURE_MAX_LEVEL to anything
// but its last level (a chain of 3 of a possible 4 would sample black), if dropping a `Texture`
// does not delete its name, or if any of it raises a GL error.
#[test]
fn uploads_hold_the_files_texels_and_the_tutorials_sampling() {
    use tutorial13::common::texture::{upload_bmp, upload_dds};
    use tutorial13::gl::context::HeadlessContext;
    use tutorial13::gl::{gl_errors, Profile};

    let context = HeadlessContext::new(Profile::Core, false).expect("a core context on llvmpipe");
    let gl = context.gl();

    let (width, height) = (6, 4);
    let bmp = read_bmp_bytes(
        &bmp_24(width, height, &pattern(width, height), false),
        Path::new("six.bmp"),
    )
    .unwrap();
    let texture = upload_bmp(gl, &bmp).unwrap();
    let mut bgr = vec![0u8; bmp.bgr.len()];
    // SAFETY: reads and queries on the current context; `bgr` holds the 6×4 BGR level 0.
    let parameters = unsafe {
        gl.bind_texture(glow::TEXTURE_2D, Some(texture.id));
        gl.pixel_store_i32(glow::PACK_ALIGNMENT, 1);
        gl.get_tex_image(
            glow::TEXTURE_2D,
            0,
            glow::BGR,
            glow::UNSIGNED_BYTE,
            glow::PixelPackData::Slice(Some(&mut bgr)),
        );
        [
            glow::TEXTURE_WRAP_S,
            glow::TEXTURE_WRAP_T,
            glow::TEXTURE_MAG_FILTER,
            glow::TEXTURE_MIN_FILTER,
        ]
        .map(|p| gl.get_tex_parameter_i32(glow::TEXTURE_2D, p) as u32)
    };
    assert_eq!(bgr, bmp.bgr);
    assert_eq!(
        parameters,
        [
            glow::REPEAT,
            glow::REPEAT,
            glow::LINEAR,
            glow::LINEAR_MIPMAP_LINEAR
        ]
    );
    assert_eq!(level_parameter(gl, 1, glow::TEXTURE_WIDTH), 3, "mipmaps");
    assert_eq!(level_parameter(gl, 2, glow::TEXTURE_HEIGHT), 1, "mipmaps");
    let bmp_id = texture.id;
    drop(texture);
    // SAFETY: a query on the current context.
    assert!(
        !unsafe { gl.is_texture(bmp_id) },
        "a dropped texture's name is deleted"
    );

    let format = DxtFormat::Dxt1;
    let (w, h, levels) = (8, 4, 3);
    let path = Path::new("three-levels.dds");
    let file = dds_file(b"DXT1", w, h, levels, chain_size(format, w, h, levels));
    let dds = read_dds_bytes(&file, path).unwrap();
    let texture = upload_dds(gl, &dds, path).unwrap();
    // SAFETY: a bind and queries on the current context.
    let max_level = unsafe {
        gl.bind_texture(glow::TEXTURE_2D, Some(texture.id));
        gl.get_tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAX_LEVEL)
    };
    assert_eq!(max_level, 2);
    for (level, data) in dds.levels.iter().enumerate() {
        let at = |p| level_parameter(gl, level as i32, p);
        assert_eq!(
            [
                at(glow::TEXTURE_WIDTH),
                at(glow::TEXTURE_HEIGHT),
                at(glow::TEXTURE_INTERNAL_FORMAT),
                at(glow::TEXTURE_COMPRESSED_IMAGE_SIZE),
            ],
            [
                data.width as i32,
                data.height as i32,
                format.gl_internal_format() as i32,
                data.data.len() as i32
            ],
            "level {level}"
        );
    }
    assert_eq!(gl_errors(gl), Vec::<u32>::new());
}
