//! The `sprite` scene's rock: a square of cobbles (its colour) and the normal map of its relief, for
//! the 2D normal-mapped lighting of article 001 ("ShaderLesson6").
//!
//! The article lights a photograph of rocks with a normal map made from it by a separate program.
//! Here both come from one height field, so that every bump in the normal map sits on a stone of the
//! colour map: rounded cobbles of different sizes (a jittered Voronoi pattern with wavy outlines),
//! grainy on top, with deep dark gaps between them.
//!
//! Orientation: picture row 0 is the top of the sprite as it appears on screen. The BMPs are stored
//! bottom row first and uploaded as they are, so GL's `t = 0` is the picture's bottom row, which the
//! scene puts at the bottom of the sprite: the picture is upright. The normal map is OpenGL's "green
//! up" (+y up the picture), which is +y up the screen, the direction `gl_FragCoord.y` grows in and so
//! the light vector's y: no flip is needed, and the scene's flip key shows what a "green down" map
//! would look like (the article's "FlipY" picture).
//!
//! Reproducible like the rest of [`super`]: integer hashing, and only `+ - * /`, `floor` and `sqrt`.

use crate::assets::{
    encode_bmp, hash3, noise_field, smoothstep, to_u8, unit, write_error, MapFiles,
};
use crate::normalmap::{normal_map, Green, HeightMap, Kernel, NormalMapOptions};
use crate::Result;

/// The two files, under assets/.
pub const FILES: MapFiles = MapFiles {
    diffuse: "sprite/diffuse.bmp",
    normal: "sprite/normal.bmp",
};

/// Side of both textures: drawn one texel per pixel where the window has room (see the scene).
pub const SPRITE_SIZE: u32 = 512;

/// The cobbles' layout and relief, all in one place: widths in texels of the 512² tile, heights
/// from 0 (the gaps' floor) to 1.
struct Layout {
    /// Cells of the jittered grid the cobbles grow from, per side.
    cells: u32,
    /// Half the width of the gap between two cobbles, the width of their rounded rim and of the
    /// slope up to their flattish middle.
    gap_half_width: f32,
    rim_width: f32,
    dome_width: f32,
    /// How far the outlines wander.
    warp: f32,
    /// Heights: gaps at the bottom, cobble tops well above them, the dome on top and the grain.
    gap_height: f32,
    stone_height: f32,
    dome_height: f32,
    grain_depth: f32,
    /// Relief of the normal map (texels of height for black-to-white): cobble rims tilt by ~50°.
    normal_strength: f32,
}

const LAYOUT: Layout = Layout {
    cells: 7,
    gap_half_width: 2.5,
    rim_width: 10.0,
    dome_width: 40.0,
    warp: 24.0,
    gap_height: 0.05,
    stone_height: 0.55,
    dome_height: 0.25,
    grain_depth: 0.12,
    normal_strength: 24.0,
};

const SEED_POINTS: u32 = 11;
const SEED_GRAIN: u32 = 12;
const SEED_MOTTLE: u32 = 13;
const SEED_STONE: u32 = 14;
const SEED_WARP: u32 = 15;

/// What the colour and the height of one texel are made from.
#[derive(Clone, Copy)]
struct RockTexel {
    /// The cobble the texel belongs to (its cell index).
    stone: u32,
    /// 0 in the gap, rising over the rim to 1 on the cobble's top.
    top: f32,
    /// 0 at the cobble's outline, rising to 1 in its middle: the pillow shape.
    dome: f32,
    grain: f32,
    mottle: f32,
}

/// One `size`² square of cobbles, row 0 = top of the picture.
struct Rock {
    texels: Vec<RockTexel>,
}

impl Rock {
    fn new(size: u32) -> Self {
        let cell = size as f32 / LAYOUT.cells as f32;
        // One feature point per cell, jittered inside its middle 80 %.
        let points: Vec<(f32, f32)> = (0..LAYOUT.cells * LAYOUT.cells)
            .map(|i| {
                let (cx, cy) = (i % LAYOUT.cells, i / LAYOUT.cells);
                let jx = 0.1 + 0.8 * unit(hash3(cx, cy, SEED_POINTS));
                let jy = 0.1 + 0.8 * unit(hash3(cy, cx, SEED_POINTS + 1));
                ((cx as f32 + jx) * cell, (cy as f32 + jy) * cell)
            })
            .collect();
        let grain = noise_field(size, &[(48, 0.4), (96, 0.35), (192, 0.25)], SEED_GRAIN);
        let mottle = noise_field(size, &[(5, 0.6), (10, 0.4)], SEED_MOTTLE);
        // Low-frequency warps of the texel positions: cobbles with wavy, not ruled, outlines.
        let warp_x = noise_field(size, &[(6, 0.6), (12, 0.4)], SEED_WARP);
        let warp_y = noise_field(size, &[(6, 0.6), (12, 0.4)], SEED_WARP + 1);
        let span = size as f32;
        let n = LAYOUT.cells as i64;
        let mut texels = Vec::with_capacity((size * size) as usize);
        for row in 0..size {
            for col in 0..size {
                let i = texels.len();
                let x = col as f32 + 0.5 + LAYOUT.warp * (warp_x[i] - 0.5);
                let y = row as f32 + 0.5 + LAYOUT.warp * (warp_y[i] - 0.5);
                let (gx, gy) = ((x / cell).floor() as i64, (y / cell).floor() as i64);
                // The points of the 5×5 cells around (wrapping, so that the square tiles), shifted
                // by whole squares where a neighbour wrapped.
                let mut near = [(0u32, 0.0f32, 0.0f32); 25];
                for (k, slot) in near.iter_mut().enumerate() {
                    let (nx, ny) = (gx + k as i64 % 5 - 2, gy + k as i64 / 5 - 2);
                    let index = (ny.rem_euclid(n) * n + nx.rem_euclid(n)) as u32;
                    let (px, py) = points[index as usize];
                    let px = px + span * nx.div_euclid(n) as f32;
                    let py = py + span * ny.div_euclid(n) as f32;
                    *slot = (index, px, py);
                }
                let d2 = |&(_, px, py): &(u32, f32, f32)| (px - x) * (px - x) + (py - y) * (py - y);
                let mut owner = near[0];
                for p in &near[1..] {
                    if d2(p) < d2(&owner) {
                        owner = *p;
                    }
                }
                // Exact distance to the cobble's outline: to the nearest bisector between its point
                // and another, (|x − q|² − |x − p|²) / (2 |q − p|).
                let mut edge = f32::MAX;
                for q in &near {
                    let (dx, dy) = (q.1 - owner.1, q.2 - owner.2);
                    let spacing = (dx * dx + dy * dy).sqrt();
                    if spacing > 0.0 {
                        edge = edge.min((d2(q) - d2(&owner)) / (2.0 * spacing));
                    }
                }
                let inside = edge - LAYOUT.gap_half_width;
                // A pillow: rising fast at the rim, flattening towards the middle.
                let below = 1.0 - (inside / LAYOUT.dome_width).clamp(0.0, 1.0);
                let pillow = 1.0 - below * below;
                texels.push(RockTexel {
                    stone: owner.0,
                    top: smoothstep(inside / LAYOUT.rim_width),
                    dome: pillow,
                    grain: grain[i],
                    mottle: mottle[i],
                });
            }
        }
        Rock { texels }
    }

    /// Gaps low and flat, cobbles rising over a rounded rim to a grainy pillow top.
    fn heights(&self) -> Vec<f32> {
        self.texels
            .iter()
            .map(|t| {
                let per_stone = 0.1 * unit(hash3(t.stone, 0, SEED_STONE));
                let stone = LAYOUT.stone_height + per_stone - LAYOUT.gap_height
                    + LAYOUT.dome_height * t.dome
                    + LAYOUT.grain_depth * (t.grain - 0.5);
                (LAYOUT.gap_height + t.top * stone).clamp(0.0, 1.0)
            })
            .collect()
    }

    /// Grey to ochre cobbles, each its own shade, blotchy and grainy; near-black gaps.
    fn diffuse_rgb(&self) -> Vec<[u8; 3]> {
        let gap = [0.08, 0.07, 0.06];
        self.texels
            .iter()
            .map(|t| {
                let warmth = unit(hash3(t.stone, 1, SEED_STONE));
                let base = [
                    0.50 + 0.16 * warmth,
                    0.47 + 0.06 * warmth,
                    0.43 - 0.08 * warmth,
                ];
                let shade = (0.75 + 0.4 * unit(hash3(t.stone, 2, SEED_STONE)))
                    * (0.7 + 0.5 * t.mottle)
                    * (0.8 + 0.4 * t.grain)
                    * (0.65 + 0.35 * t.top);
                let mut c = gap;
                for k in 0..3 {
                    c[k] += t.top * (base[k] * shade - c[k]);
                }
                c.map(to_u8)
            })
            .collect()
    }
}

/// The scene's two files, as (path under assets/, bytes): the colour map and its normal map, both
/// 24-bit BMPs of [`SPRITE_SIZE`]².
pub fn generate() -> Result<crate::assets::GeneratedFiles> {
    let rock = Rock::new(SPRITE_SIZE);
    let diffuse = encode_bmp(&rock.diffuse_rgb(), SPRITE_SIZE)
        .map_err(|reason| write_error(FILES.diffuse, reason))?;
    let normals = normal_map(
        &HeightMap {
            width: SPRITE_SIZE,
            height: SPRITE_SIZE,
            values: rock.heights(),
        },
        NormalMapOptions {
            strength: LAYOUT.normal_strength,
            kernel: Kernel::Sobel,
            // +y up the picture = up the screen, where the light vector's y points.
            green: Green::Up,
            two_channel: false,
        },
    );
    let normal =
        encode_bmp(&normals, SPRITE_SIZE).map_err(|reason| write_error(FILES.normal, reason))?;
    Ok(vec![(FILES.diffuse, diffuse), (FILES.normal, normal)])
}

/// The rock's height field (row 0 = top), for tests that check the normal map against it.
pub fn rock_height_map(size: u32) -> Vec<f32> {
    Rock::new(size).heights()
}
