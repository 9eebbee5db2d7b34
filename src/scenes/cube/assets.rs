//! The cube scene's textures: one seamless tile of irregular stones and its normal map.
//!
//! Article 003 puts "a repeating stone texture" on its cube and makes the normal map from it with
//! GIMP's normalmap plugin. Neither can be copied in, so both are made here, as the rest of assets/:
//! the stones' heights are laid out first, the colour follows the same stones, and the normal map is
//! the crate's height-map tool ([`crate::normalmap`]) run on those heights.
//!
//! * `cube/diffuse.bmp`: grey-brown stones, each its own shade, blotchy and grainy, darker towards
//!   their rounded edges, set in dark mortar.
//! * `cube/normal.bmp`: Sobel derivatives, OpenGL's "green up" convention.
//!
//! Orientation: picture row 0 is the top of a face. A BMP is stored bottom row first and
//! `load_bmp_custom` uploads it as it is, so GL's t = 0 is the picture's bottom row. The cube's V
//! grows up each face (see `scenes/cube.rs`), so its bitangent dP/dV points up the picture: the
//! green-up convention's +y, and the tangent dP/dU its +x. No turn or flip is needed, unlike the
//! cylinder's maps (see the parent module).
//!
//! Same rules as the parent module: deterministic to the byte (integer hash noise, only `+ - * /`,
//! `floor` and `sqrt` in the maths), and small: 256² 24-bit BMPs of 192 KiB each.

use crate::assets::{
    encode_bmp, hash3, noise_field, smoothstep, to_u8, unit, write_error, MapFiles,
};
use crate::normalmap::{normal_map, HeightMap, NormalMapOptions};
use crate::Result;

/// The cube's files, under assets/.
pub const FILES: MapFiles = MapFiles {
    diffuse: "cube/diffuse.bmp",
    normal: "cube/normal.bmp",
};

/// Side of both textures.
pub const TEXTURE_SIZE: u32 = 256;
/// Stones per tile side: a jittered 5×5 grid of cell centres, so about 25 stones per face.
const STONES_PER_SIDE: u32 = 5;
/// How far a stone's centre may wander from its cell's centre, as a fraction of the cell.
const JITTER: f32 = 0.7;
/// Widths in texels of a 256² tile: half the mortar joint, and the rounded shoulder of a stone.
const JOINT_HALF_WIDTH: f32 = 2.0;
const SHOULDER_WIDTH: f32 = 16.0;
/// Heights (0..1): the mortar lies low and flat, stone faces high, each stone a little higher or
/// lower than its neighbours, with a faint grain.
const MORTAR_HEIGHT: f32 = 0.1;
const STONE_HEIGHT: f32 = 0.7;
const STONE_HEIGHT_SPREAD: f32 = 0.12;
const GRAIN_DEPTH: f32 = 0.05;
/// Texels of relief the full height range stands for (the tool's `--strength`): the shoulders tilt
/// the normal by up to about 60°, the grain by a few degrees.
pub const NORMAL_STRENGTH: f32 = 12.0;

const SEED_STONE: u32 = 11;
const SEED_GRAIN: u32 = 12;
const SEED_MOTTLE: u32 = 13;

/// The cube's two files, in memory: (path under assets/, bytes).
pub fn generate() -> Result<crate::assets::GeneratedFiles> {
    let stones = Stones::new(TEXTURE_SIZE);
    let diffuse = encode_bmp(&stones.diffuse_rgb(), TEXTURE_SIZE)
        .map_err(|reason| write_error(FILES.diffuse, reason))?;
    let normals = stone_normal_map(&stones.heights(), TEXTURE_SIZE);
    let normal =
        encode_bmp(&normals, TEXTURE_SIZE).map_err(|reason| write_error(FILES.normal, reason))?;
    Ok(vec![(FILES.diffuse, diffuse), (FILES.normal, normal)])
}

/// The normal map of a stone height map (`size²`, row 0 = top), as RGB texels in the same order:
/// the height-map tool with its defaults (Sobel, green up) at [`NORMAL_STRENGTH`].
pub fn stone_normal_map(heights: &[f32], size: u32) -> Vec<[u8; 3]> {
    let map = HeightMap {
        width: size,
        height: size,
        values: heights.to_vec(),
    };
    normal_map(
        &map,
        NormalMapOptions {
            strength: NORMAL_STRENGTH,
            ..Default::default()
        },
    )
}

/// What one texel of the tile is made from.
#[derive(Clone, Copy)]
struct StoneTexel {
    /// The stone this texel belongs to (its cell, wrapped), or `None` in the mortar.
    stone: Option<u32>,
    /// 0 at the stone's edge, rising over its rounded shoulder to 1 on its face.
    shoulder: f32,
    grain: f32,
    mottle: f32,
}

/// One tile of stones sampled at `size²` texels, row 0 = top of the picture.
struct Stones {
    texels: Vec<StoneTexel>,
}

impl Stones {
    /// Each texel belongs to the nearest stone centre (a Voronoi cell, wrapping at the tile's
    /// edges so that the tile repeats); its distance to the nearest cell border decides whether it
    /// is mortar and how far up the stone's shoulder it is.
    fn new(size: u32) -> Self {
        let n = STONES_PER_SIDE as i32;
        let texel = 1.0 / size as f32;
        let grain = noise_field(size, &[(32, 0.5), (64, 0.5)], SEED_GRAIN);
        let mottle = noise_field(size, &[(4, 0.5), (8, 0.5)], SEED_MOTTLE);
        // The jittered centre of cell (i, j), i and j wrapped into the tile; in tile units.
        let centre = |i: i32, j: i32| {
            let (wi, wj) = (i.rem_euclid(n) as u32, j.rem_euclid(n) as u32);
            let jitter =
                |salt| (1.0 - JITTER) * 0.5 + JITTER * unit(hash3(wi, wj * 4 + salt, SEED_STONE));
            (
                (i as f32 + jitter(0)) / n as f32,
                (j as f32 + jitter(1)) / n as f32,
            )
        };
        let mut texels = Vec::with_capacity((size * size) as usize);
        for row in 0..size {
            let y = (row as f32 + 0.5) * texel;
            let cell_j = (y * n as f32).floor() as i32;
            for col in 0..size {
                let i = texels.len();
                let x = (col as f32 + 0.5) * texel;
                let cell_i = (x * n as f32).floor() as i32;
                // Centres of the 5×5 cells around: enough for the nearest and for every border near it.
                let mut candidates = [(0i32, 0i32, 0.0f32, 0.0f32); 25];
                let mut k = 0;
                for dj in -2..=2 {
                    for di in -2..=2 {
                        let (cx, cy) = centre(cell_i + di, cell_j + dj);
                        candidates[k] = (cell_i + di, cell_j + dj, cx, cy);
                        k += 1;
                    }
                }
                let d2 = |c: &(i32, i32, f32, f32)| (c.2 - x) * (c.2 - x) + (c.3 - y) * (c.3 - y);
                let nearest = candidates
                    .iter()
                    .copied()
                    .reduce(|a, b| if d2(&b) < d2(&a) { b } else { a })
                    .unwrap_or_default();
                // Distance to the border with each other centre: the perpendicular bisector.
                let mut border = f32::MAX;
                for other in &candidates {
                    if (other.0, other.1) == (nearest.0, nearest.1) {
                        continue;
                    }
                    let (ex, ey) = (other.2 - nearest.2, other.3 - nearest.3);
                    let length = (ex * ex + ey * ey).sqrt();
                    let (mx, my) = ((other.2 + nearest.2) * 0.5, (other.3 + nearest.3) * 0.5);
                    border = border.min(((mx - x) * ex + (my - y) * ey) / length);
                }
                let inside = border / texel - JOINT_HALF_WIDTH;
                let stone = (inside > 0.0).then(|| {
                    let (wi, wj) = (nearest.0.rem_euclid(n), nearest.1.rem_euclid(n));
                    (wj * n + wi) as u32
                });
                // A quarter circle: steep at the edge, flat on the face.
                let t = (inside / SHOULDER_WIDTH).clamp(0.0, 1.0);
                let shoulder = (1.0 - (1.0 - t) * (1.0 - t)).sqrt();
                texels.push(StoneTexel {
                    stone,
                    shoulder: if stone.is_some() { shoulder } else { 0.0 },
                    grain: grain[i],
                    mottle: mottle[i],
                });
            }
        }
        Stones { texels }
    }

    /// Mortar flat at [`MORTAR_HEIGHT`]; each stone rises over its shoulder to its own height, with
    /// a faint grain on its face.
    fn heights(&self) -> Vec<f32> {
        self.texels
            .iter()
            .map(|t| match t.stone {
                None => MORTAR_HEIGHT,
                Some(stone) => {
                    let own = STONE_HEIGHT
                        + STONE_HEIGHT_SPREAD * (unit(hash3(stone, 1, SEED_STONE)) - 0.5)
                        + GRAIN_DEPTH * (t.grain - 0.5);
                    (MORTAR_HEIGHT + t.shoulder * (own - MORTAR_HEIGHT)).clamp(0.0, 1.0)
                }
            })
            .collect()
    }

    /// Stones in greys from warm to cool, each its own shade, blotchy and grainy and darker down
    /// their shoulders; the mortar dark and brownish.
    fn diffuse_rgb(&self) -> Vec<[u8; 3]> {
        self.texels
            .iter()
            .map(|t| {
                let mortar_shade = 0.8 + 0.4 * t.grain;
                let mortar = [0.17, 0.15, 0.13].map(|m| m * mortar_shade);
                let Some(stone) = t.stone else {
                    return mortar.map(to_u8);
                };
                // Light stones: the article's lighting is dim (at most 0.09 + 0.4 of the texel
                // before the highlight).
                let grey = 0.6 + 0.22 * unit(hash3(stone, 2, SEED_STONE));
                let warmth = unit(hash3(stone, 3, SEED_STONE));
                let base = [grey + 0.05 * warmth, grey, grey - 0.04 - 0.06 * warmth];
                let shade = (0.78 + 0.4 * t.mottle)
                    * (0.88 + 0.24 * t.grain)
                    * (0.6 + 0.4 * smoothstep(t.shoulder * 1.5));
                let cover = (t.shoulder * 6.0).min(1.0);
                let mut c = mortar;
                for k in 0..3 {
                    c[k] += cover * (base[k] * shade - c[k]);
                }
                c.map(to_u8)
            })
            .collect()
    }
}
