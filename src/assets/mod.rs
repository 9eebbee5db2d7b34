//! The project's own cylinder, brick textures and normal map, made by code, and the helpers every
//! scene's generated textures share (noise, hashing, BMP and DDS encoding, writing). The other
//! scenes' generators sit in their folders (`scenes/<name>/assets.rs`).
//!
//! The tutorial's `cylinder.obj`, `diffuse.DDS`, `normal.bmp` and `specular.DDS` cannot be
//! redistributed, so [`make_assets`] writes look-alikes with the same conventions: the same cylinder
//! (radius 1, height 2, 32 segments, UVs wrapping ~3.7 times around), DXT3 textures of 1024² with 11
//! mip levels and a 24-bit 1024² BMP normal map, all from one brick layout so that bumps, colour and
//! shininess line up.
//!
//! Output is byte-for-byte reproducible: the noise is a hand-written integer hash, nothing is iterated
//! out of a hash map, nothing runs on threads, and the texture maths uses only `+ - * /`, `floor` and
//! `sqrt` (exactly rounded in IEEE 754, unlike `sin` or `powf`, whose last bit may differ between C
//! libraries). The OBJ's `sin`/`cos` are printed with six decimals, far above that last bit.
//!
//! # Orientation (worked out from the tutorial's loaders and shaders)
//!
//! Picture row 0 is the top of the brick wall as it appears on the cylinder (V = 1 in the OBJ).
//!
//! * DDS: the loader negates V, so the diffuse and specular textures are sampled at GL
//!   `t = -V ≡ 1 - V`. GL puts the file's first row at `t = 0`, so the first row stored is the one
//!   shown at the top of the cylinder: picture row 0 first ("upside down" for GL, the usual DDS
//!   order).
//! * BMP: the fragment shader samples the normal map at `(UV.x, -UV.y) = (U, V)`, so `t = V`. A BMP
//!   is stored bottom row first and uploaded as is, so the picture, as an image viewer shows it, is
//!   upright on the cylinder: BMP picture row `r` lands on the same V as DDS row `r`, and the bumps
//!   line up with the colours.
//! * Normal map channels: the tutorial's tangent is `dP/dU` and its bitangent `dP/d(-V)` (the UV
//!   after the loader's negation), and because that frame is mirrored, its handedness step flips T.
//!   With U growing to the right and V upwards on the cylinder, T therefore points *left* and B
//!   *down* across the picture. Red must then grow with `+dh/dx` and green with `+dh/dy` (x to the
//!   right, y up the picture): the usual OpenGL normal map turned by 180°. Made that way, a brick
//!   lit from above has bright top edges (checked in `tests/all/assets.rs` with the crate's own tangent
//!   code). The tutorial's own `normal.bmp` agrees on red but has green the other way round.

use std::path::{Path, PathBuf};

mod fallback;
pub mod obj_text;

pub(crate) use fallback::say_taken_from_crate;
pub use fallback::{crate_assets_dir, find_assets, taken_from_crate, AssetFiles};

use self::obj_text::tutorial_cylinder_obj_text;
use crate::files::write_bytes_atomically;
use crate::normalmap::{normal_map, HeightMap, Kernel, NormalMapOptions};
use crate::{Error, Result};

/// The files [`make_assets`] writes, as the tutorial names them.
pub const ASSET_FILES: [&str; 4] = ["cylinder.obj", "diffuse.DDS", "normal.bmp", "specular.DDS"];

/// Side of every texture, as the tutorial's.
const TEXTURE_SIZE: u32 = 1024;
/// Segments around the cylinder, as the tutorial's.
const CYLINDER_SEGMENTS: u32 = 32;
/// Bump strength of `normal.bmp` (height units per texel → slope): the grain tilts the normal by a
/// few degrees, the bevels by up to ~40°, the walls of the pits by up to ~60°.
const NORMAL_STRENGTH: f32 = 14.0;

/// What [`make_assets`] did with each file.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AssetsWritten {
    /// Files that were not there, now written.
    pub created: Vec<PathBuf>,
    /// Files that were there with the same bytes, left untouched.
    pub unchanged: Vec<PathBuf>,
    /// Files that were there with other bytes, replaced (only with `force`).
    pub replaced: Vec<PathBuf>,
}

/// Generated files: each one's path under the assets folder, and its bytes.
pub type GeneratedFiles = Vec<(&'static str, Vec<u8>)>;

/// A scene's two generated maps, as paths under the assets folder: defined once, read by the
/// generator that writes them and by the scene that loads them (`gl::Maps::load`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MapFiles {
    pub diffuse: &'static str,
    pub normal: &'static str,
}

impl MapFiles {
    /// The two paths, the diffuse map first (as `gl::Maps::load` takes them).
    pub const fn names(&self) -> [&'static str; 2] {
        [self.diffuse, self.normal]
    }
}

/// Writes `files` (paths under the assets folder, and bytes) into `out_dir`, creating folders. The
/// generators are deterministic: same bytes every run, on any machine.
///
/// A file already there with other bytes (say the tutorial's own `normal.bmp`) is never replaced
/// unless `force` is set: without it, nothing at all is written and the error names every such file.
/// Each file is written atomically, so an interrupted run leaves whole files only.
pub fn make_assets(out_dir: &Path, files: &GeneratedFiles, force: bool) -> Result<AssetsWritten> {
    let mut written = AssetsWritten::default();
    let mut differing = Vec::new();
    let mut to_write = Vec::new();
    for (name, bytes) in files {
        let path = out_dir.join(name);
        match std::fs::read(&path) {
            Ok(existing) if existing == *bytes => written.unchanged.push(path),
            Ok(_) => {
                differing.push(path.clone());
                to_write.push((path, bytes));
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => to_write.push((path, bytes)),
            Err(e) => return Err(Error::io(&path, e)),
        }
    }
    if !differing.is_empty() && !force {
        return Err(Error::WouldOverwrite { paths: differing });
    }
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    for (path, bytes) in to_write {
        // A scene's own files go in a folder of their own (e.g. assets/wall/).
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        }
        write_bytes_atomically(&path, bytes)?;
        if differing.contains(&path) {
            written.replaced.push(path);
        } else {
            written.created.push(path);
        }
    }
    Ok(written)
}

/// The cylinder's four generated files (its path under assets/, and its bytes), in [`ASSET_FILES`]
/// order, made in memory before anything is written. Every scene's files: `scenes::generate_assets`.
pub fn generate_cylinder_assets() -> Result<GeneratedFiles> {
    let wall = BrickWall::new(TEXTURE_SIZE);
    let [obj, diffuse, normal, specular] = ASSET_FILES;
    let cylinder = tutorial_cylinder_obj_text(CYLINDER_SEGMENTS).into_bytes();
    let normals = normal_map_from_height(&wall.heights(), TEXTURE_SIZE, NORMAL_STRENGTH);
    let bmp = encode_bmp(&normals, TEXTURE_SIZE).map_err(|reason| write_error(normal, reason))?;
    let diffuse_dds = encode_dds_dxt3(wall.diffuse_rgba(), TEXTURE_SIZE)
        .map_err(|reason| write_error(diffuse, reason))?;
    let specular_dds = encode_dds_dxt3(wall.specular_rgba(), TEXTURE_SIZE)
        .map_err(|reason| write_error(specular, reason))?;
    Ok(vec![
        (obj, cylinder),
        (diffuse, diffuse_dds),
        (normal, bmp),
        (specular, specular_dds),
    ])
}

pub fn write_error(path: impl Into<PathBuf>, reason: String) -> Error {
    Error::Write {
        path: path.into(),
        reason,
    }
}

// ---------------------------------------------------------------------------------------------
// Brick wall

/// Rows of bricks per texture tile and bricks per row, as in the tutorial's texture (running bond:
/// odd rows shifted by half a brick; an even number of rows keeps the tile seamless).
const BRICK_ROWS: u32 = 6;
const BRICKS_PER_ROW: u32 = 3;
/// Widths in tile units (1/1024 of a tile ≈ one texel of the committed textures).
const MORTAR_HALF_WIDTH: f32 = 7.0 / 1024.0;
const CORNER_RADIUS: f32 = 12.0 / 1024.0;
const BEVEL_WIDTH: f32 = 14.0 / 1024.0;
const EDGE_WOBBLE: f32 = 5.0 / 1024.0;
const PITS_PER_BRICK: u32 = 16;
/// Heights: the mortar is one flat level, the brick faces sit well above it.
const MORTAR_HEIGHT: f32 = 0.2;
const BRICK_HEIGHT: f32 = 0.72;
const GRAIN_DEPTH: f32 = 0.14;
const PIT_DEPTH: f32 = 0.3;

/// Seeds of the independent noise fields.
const SEED_GRAIN: u32 = 1;
const SEED_EDGE: u32 = 2;
const SEED_MOTTLE: u32 = 3;
const SEED_BRICK: u32 = 4;
const SEED_PIT: u32 = 5;

/// What the colour, shininess and height of one texel are made from.
#[derive(Clone, Copy)]
struct WallTexel {
    /// Index of the brick, `None` in the mortar.
    brick: Option<u32>,
    /// 0 in the mortar, rising over the bevel to 1 on the brick's face.
    face: f32,
    /// Fine grain, 0..1.
    grain: f32,
    /// Blotchy low-frequency noise for colour, 0..1.
    mottle: f32,
    /// Depth of a pit at this texel, 0 (none) .. 1 (bottom of a pit).
    pit: f32,
}

/// One tile of brick wall sampled at `size`² texels, row 0 = top of the picture.
struct BrickWall {
    texels: Vec<WallTexel>,
}

impl BrickWall {
    fn new(size: u32) -> Self {
        let scale = size as f32;
        let brick_w = scale / BRICKS_PER_ROW as f32;
        let brick_h = scale / BRICK_ROWS as f32;
        let pits = pit_field(size);
        let wobble = noise_field(size, &[(32, 0.6), (64, 0.4)], SEED_EDGE);
        let grain = noise_field(size, &[(64, 0.35), (128, 0.35), (256, 0.3)], SEED_GRAIN);
        let mottle = noise_field(size, &[(6, 0.6), (12, 0.4)], SEED_MOTTLE);
        let mut texels = Vec::with_capacity((size * size) as usize);
        for row in 0..size {
            let v = (row as f32 + 0.5) / scale;
            let brick_row = (v * BRICK_ROWS as f32) as u32;
            let fy = v * BRICK_ROWS as f32 - brick_row as f32;
            let shift = if brick_row % 2 == 1 { 0.5 } else { 0.0 };
            for col in 0..size {
                let i = texels.len();
                let u = (col as f32 + 0.5) / scale;
                let bx = u * BRICKS_PER_ROW as f32 + shift;
                let brick_col = bx.floor();
                // Brick-local x, continuous across the tile's edge for the brick cut by it.
                let fx = bx - brick_col;
                let brick = brick_row * BRICKS_PER_ROW + brick_col as u32 % BRICKS_PER_ROW;

                // Signed distance (texels) inside the brick's rounded rectangle, wobbled so that
                // the edges look chipped rather than ruled.
                let ex = fx.min(1.0 - fx) * brick_w - MORTAR_HALF_WIDTH * scale;
                let ey = fy.min(1.0 - fy) * brick_h - MORTAR_HALF_WIDTH * scale;
                let r = CORNER_RADIUS * scale;
                let inside = if ex < r && ey < r {
                    r - ((r - ex) * (r - ex) + (r - ey) * (r - ey)).sqrt()
                } else {
                    ex.min(ey)
                } + (wobble[i] - 0.5) * 2.0 * EDGE_WOBBLE * scale;

                let (brick, face, pit) = if inside > 0.0 {
                    let face = smoothstep(inside / (BEVEL_WIDTH * scale));
                    (Some(brick), face, pits[i])
                } else {
                    (None, 0.0, 0.0)
                };
                texels.push(WallTexel {
                    brick,
                    face,
                    grain: grain[i],
                    mottle: mottle[i],
                    pit,
                });
            }
        }
        BrickWall { texels }
    }

    /// Mortar exactly flat at [`MORTAR_HEIGHT`]; bricks rise over the bevel to a grainy, pitted face.
    fn heights(&self) -> Vec<f32> {
        self.texels
            .iter()
            .map(|t| {
                let face = BRICK_HEIGHT - MORTAR_HEIGHT + GRAIN_DEPTH * (t.grain - 0.5)
                    - PIT_DEPTH * t.pit;
                (MORTAR_HEIGHT + t.face * face).clamp(0.0, 1.0)
            })
            .collect()
    }

    /// Red-brown bricks (about one in ten brownish grey), each its own shade, blotchy and grainy, darker in
    /// pits and towards the bevel; dark grey mortar. Alpha 255 (the tutorial ignores it).
    fn diffuse_rgba(&self) -> Vec<u8> {
        let mortar = [0.23, 0.21, 0.20];
        let mut out = Vec::with_capacity(self.texels.len() * 4);
        for t in &self.texels {
            let mortar_shade = 0.8 + 0.4 * t.grain;
            let mut c = mortar.map(|m| m * mortar_shade);
            if let Some(brick) = t.brick {
                let h = hash3(brick, 0, SEED_BRICK);
                let base = if unit(h) < 0.1 {
                    [0.36, 0.31, 0.28]
                } else {
                    let redness = unit(hash3(brick, 1, SEED_BRICK));
                    [0.40 + 0.14 * redness, 0.20 + 0.03 * redness, 0.15]
                };
                let shade = (0.8 + 0.35 * unit(hash3(brick, 2, SEED_BRICK)))
                    * (0.75 + 0.5 * t.mottle)
                    * (0.85 + 0.3 * t.grain)
                    * (1.0 - 0.6 * t.pit)
                    * (0.7 + 0.3 * t.face);
                let cover = (t.face * 4.0).min(1.0);
                for k in 0..3 {
                    c[k] += cover * (base[k] * shade - c[k]);
                }
            }
            out.extend(c.map(to_u8));
            out.push(255);
        }
        out
    }

    /// The tutorial's "specular texture": brick faces light grey with noise, mortar and pits dark.
    fn specular_rgba(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.texels.len() * 4);
        for t in &self.texels {
            let s = match t.brick {
                Some(brick) => {
                    let per_brick = 0.85 + 0.3 * unit(hash3(brick, 3, SEED_BRICK));
                    t.face
                        * per_brick
                        * (0.3 + 0.45 * t.grain + 0.25 * t.mottle)
                        * (1.0 - 0.8 * t.pit)
                }
                None => 0.0,
            };
            let s = to_u8(s);
            out.extend([s, s, s, 255]);
        }
        out
    }
}

/// Depth of the pits, 0 (none) .. 1 (bottom of a pit): round dents placed at random in each brick,
/// stamped one by one (wrapping at the tile's edge) rather than searched for at every texel. They
/// stay clear of the brick's edges, so they never reach the mortar.
fn pit_field(size: u32) -> Vec<f32> {
    let n = size as usize;
    let scale = size as f32;
    let mut field = vec![0.0f32; n * n];
    for brick in 0..BRICK_ROWS * BRICKS_PER_ROW {
        let (brick_row, brick_col) = (brick / BRICKS_PER_ROW, brick % BRICKS_PER_ROW);
        let shift = if brick_row % 2 == 1 { 0.5 } else { 0.0 };
        for k in 0..PITS_PER_BRICK {
            let h = |salt: u32| unit(hash3(brick, k * 4 + salt, SEED_PIT));
            // Centre and radius in texels.
            let cx = (brick_col as f32 - shift + 0.1 + 0.8 * h(0)) / BRICKS_PER_ROW as f32 * scale;
            let cy = (brick_row as f32 + 0.15 + 0.7 * h(1)) / BRICK_ROWS as f32 * scale;
            let radius = (2.5 + 9.0 * h(2) * h(3)) / 1024.0 * scale;
            let cols = (cx - radius - 0.5).floor() as i64..=(cx + radius - 0.5).ceil() as i64;
            let rows = (cy - radius - 0.5).floor() as i64..=(cy + radius - 0.5).ceil() as i64;
            for row in rows {
                for col in cols.clone() {
                    let (dx, dy) = (col as f32 + 0.5 - cx, row as f32 + 0.5 - cy);
                    let q = (dx * dx + dy * dy) / (radius * radius);
                    if q < 1.0 {
                        let i = row.rem_euclid(n as i64) as usize * n
                            + col.rem_euclid(n as i64) as usize;
                        field[i] = field[i].max((1.0 - q) * (1.0 - q));
                    }
                }
            }
        }
    }
    field
}

/// `size * size` heights in 0..1, row 0 = top of the picture: one seamless tile of running-bond
/// brick wall (6 rows of 3 bricks), mortar low and exactly flat, brick faces high, bevelled and
/// slightly rough.
pub fn brick_height_map(size: u32) -> Vec<f32> {
    BrickWall::new(size).heights()
}

// ---------------------------------------------------------------------------------------------
// Normal map

/// Tangent-space normals of a `size * size` height map (row 0 = top), as RGB, row 0 = top: the
/// height-map tool ([`crate::normalmap`]) with central differences, on the height negated.
///
/// The tool stores OpenGL's convention, n = normalize(−∂h/∂x, −∂h/∂y, 1) with y up the picture. The
/// project's maps must be that turned by 180° (red growing with +∂h/∂x, green with +∂h/∂y; see the
/// module comment), which is exactly the tool's output for −h. Central differences (not the tool's
/// default Sobel) keep `assets/normal.bmp` the bytes it has always been.
pub fn normal_map_from_height(height: &[f32], size: u32, strength: f32) -> Vec<[u8; 3]> {
    assert_eq!(
        height.len(),
        (size as usize).pow(2),
        "height map must hold size * size values"
    );
    let negated = HeightMap {
        width: size,
        height: size,
        values: height.iter().map(|h| -h).collect(),
    };
    let options = NormalMapOptions {
        strength,
        kernel: Kernel::Central,
        ..Default::default()
    };
    normal_map(&negated, options)
}

/// 24-bit uncompressed BMP (54-byte header, BI_RGB, bottom row first), what `loadBMP_custom` reads.
/// `rgb` is `size × size` texels, picture row 0 (top) first. Public for tests that need flat maps.
pub fn encode_bmp(rgb: &[[u8; 3]], size: u32) -> std::result::Result<Vec<u8>, String> {
    let flat: Vec<u8> = rgb.iter().flatten().copied().collect();
    let mut bytes = Vec::with_capacity(54 + flat.len());
    image::codecs::bmp::BmpEncoder::new(&mut bytes)
        .encode(&flat, size, size, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}

// ---------------------------------------------------------------------------------------------
// DDS

/// DXT3 (BC2) like the tutorial's files, with the full mip chain (down to 1×1) made by 2×2 box
/// filtering; picture row 0 stored first (see the module comment). Range fit rather than texpresso's
/// default cluster fit: the whole of `make_assets` takes ~1.2 s instead of ~5.8 s in a debug build,
/// for ~2 dB less PSNR on level 0 (42 instead of 44 dB on the diffuse map), invisible on noisy bricks.
pub fn encode_dds_dxt3(rgba: Vec<u8>, size: u32) -> std::result::Result<Vec<u8>, String> {
    let format = texpresso::Format::Bc2;
    let params = texpresso::Params {
        algorithm: texpresso::Algorithm::RangeFit,
        ..Default::default()
    };
    let mut data = Vec::new();
    let mut level = rgba;
    let mut side = size as usize;
    let mut levels = 0;
    loop {
        let start = data.len();
        data.resize(start + format.compressed_size(side, side), 0);
        format.compress(&level, side, side, params, &mut data[start..]);
        levels += 1;
        if side == 1 {
            break;
        }
        level = half_size(&level, side);
        side /= 2;
    }

    let mut dds = ddsfile::Dds::new_d3d(ddsfile::NewD3dParams {
        height: size,
        width: size,
        depth: None,
        format: ddsfile::D3DFormat::DXT3,
        mipmap_levels: Some(levels),
        caps2: None,
    })
    .map_err(|e| e.to_string())?;
    // DXT3 carries explicit alpha; the tutorial's files (made by a DirectX tool) say so too.
    dds.header.spf.flags |= ddsfile::PixelFormatFlags::ALPHA_PIXELS;
    if dds.data.len() != data.len() {
        return Err(format!(
            "mip chain is {} bytes, the DDS header expects {}",
            data.len(),
            dds.data.len()
        ));
    }
    dds.data = data;
    let mut bytes = Vec::new();
    dds.write(&mut bytes).map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// The next mip level: each texel the rounded mean of a 2×2 block (`side` even).
fn half_size(rgba: &[u8], side: usize) -> Vec<u8> {
    let half = side / 2;
    let mut out = Vec::with_capacity(half * half * 4);
    for row in 0..half {
        let top = &rgba[2 * row * side * 4..][..side * 4];
        let bottom = &rgba[(2 * row + 1) * side * 4..][..side * 4];
        for col in 0..half {
            for k in 0..4 {
                let i = col * 8 + k;
                let sum = u32::from(top[i])
                    + u32::from(top[i + 4])
                    + u32::from(bottom[i])
                    + u32::from(bottom[i + 4]);
                out.push(((sum + 2) / 4) as u8);
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Deterministic noise

/// A 32-bit integer hash of three values (multiply-xorshift; the finaliser is MurmurHash3's).
pub fn hash3(a: u32, b: u32, c: u32) -> u32 {
    let mut h = a.wrapping_mul(0x9E37_79B1)
        ^ b.wrapping_mul(0x85EB_CA77).rotate_left(13)
        ^ c.wrapping_mul(0xC2B2_AE3D).rotate_left(26);
    h ^= h >> 16;
    h = h.wrapping_mul(0x85EB_CA6B);
    h ^= h >> 13;
    h = h.wrapping_mul(0xC2B2_AE35);
    h ^ (h >> 16)
}

/// The top 24 bits of a hash as a float in [0, 1).
pub fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

pub fn smoothstep(t: f32) -> f32 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Value noise on a `cells`² lattice over the tile (wrapping at its edges), summed over octaves
/// `(cells, weight)` with weights adding up to 1, sampled at the `size`² texel centres; 0..1.
///
/// Whole fields at once: the interpolation weights depend on the column or the row only, so they are
/// computed once per octave, which keeps debug builds quick.
pub fn noise_field(size: u32, octaves: &[(u32, f32)], seed: u32) -> Vec<f32> {
    let n = size as usize;
    let mut field = vec![0.0f32; n * n];
    for &(cells, weight) in octaves {
        let lattice: Vec<f32> = (0..cells * cells)
            .map(|i| {
                unit(hash3(
                    i % cells,
                    i / cells,
                    seed.wrapping_mul(0x1000_0001) ^ cells,
                ))
            })
            .collect();
        // For each texel centre along an axis: the two lattice lines around it and the blend.
        let axis: Vec<(usize, usize, f32)> = (0..size)
            .map(|i| {
                let g = (i as f32 + 0.5) / size as f32 * cells as f32;
                let g0 = g.floor();
                let i0 = g0 as u32 % cells;
                (i0 as usize, ((i0 + 1) % cells) as usize, smoothstep(g - g0))
            })
            .collect();
        let cells = cells as usize;
        for (row, &(y0, y1, ty)) in axis.iter().enumerate() {
            let (line0, line1) = (
                &lattice[y0 * cells..][..cells],
                &lattice[y1 * cells..][..cells],
            );
            for (out, &(x0, x1, tx)) in field[row * n..][..n].iter_mut().zip(&axis) {
                let top = line0[x0] + tx * (line0[x1] - line0[x0]);
                let bottom = line1[x0] + tx * (line1[x1] - line1[x0]);
                *out += weight * (top + ty * (bottom - top));
            }
        }
    }
    field
}

pub fn to_u8(x: f32) -> u8 {
    (x * 255.0).round().clamp(0.0, 255.0) as u8
}
