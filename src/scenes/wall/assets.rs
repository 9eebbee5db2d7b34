//! The `wall` scene's textures: article 004's stone wall, made here (the article's pictures cannot be
//! redistributed). Irregular stones (the cells of a jittered grid, nearest-point regions) set in
//! mortar: one height field gives the colour's shading and, through the `normalmap` tool's function,
//! the normal map in OpenGL's convention (green up the picture, the article's and Tutorial 13's).
//! The texture tiles: cells, noise and the normal map's derivatives all wrap at the edges.
//!
//! Reproducible byte for byte like the rest of the generated assets: integer hashing, and only `+ - * /`,
//! `floor` and `sqrt` on floats.

use crate::assets::{
    encode_bmp, hash3, noise_field, smoothstep, to_u8, unit, write_error, MapFiles,
};
use crate::normalmap::{normal_map, HeightMap, NormalMapOptions};
use crate::Result;

/// Where the files go under assets/.
pub const FILES: MapFiles = MapFiles {
    diffuse: "wall/diffuse.bmp",
    normal: "wall/normal.bmp",
};

/// Side of both textures: small, the square covers about 370 pixels of the window.
const SIZE: u32 = 256;
/// Stones per side of the tile.
const STONES: u32 = 5;
/// Half the width of a mortar joint, in texels.
const MORTAR: f32 = 2.5;
/// How far from its edge a stone is rounded off, in texels.
const BEVEL: f32 = 9.0;
/// Seeds the wall's hashes and noise ("stone").
const SEED: u32 = 0x0005_707e;
/// Texels of relief for the full height range (see `tutorial13 normalmap --strength`).
const STRENGTH: f32 = 5.0;

/// The two files, in memory.
pub fn generate() -> Result<crate::assets::GeneratedFiles> {
    let stones = Stones::new();
    let grain = noise_field(SIZE, &[(16, 0.45), (32, 0.35), (64, 0.2)], SEED);
    let n = SIZE as usize;
    let mut heights = Vec::with_capacity(n * n);
    let mut colours = Vec::with_capacity(n * n);
    for row in 0..SIZE {
        for col in 0..SIZE {
            let (stone, edge) = stones.nearest(col as f32 + 0.5, row as f32 + 0.5);
            let grain = grain[row as usize * n + col as usize] - 0.5;
            // Sunk joints of sandy mortar.
            let shade = 0.92 + 0.2 * grain;
            let mortar_height = 0.08 + 0.1 * grain;
            let mortar = [150.0 * shade, 141.0 * shade, 124.0 * shade];
            // Each stone its own grey-brown, domed towards its middle, with a rough face.
            let tint = unit(hash3(stone, 7, SEED));
            let tone = unit(hash3(stone, 11, SEED));
            let dome = smoothstep((edge - MORTAR) / BEVEL);
            let stone_height = 0.45 + 0.35 * dome + 0.1 * tone + 0.12 * grain;
            let shade = (0.55 + 0.5 * stone_height) * (0.8 + 0.4 * tone);
            let base = [118.0 + 30.0 * tint, 110.0 + 16.0 * tint, 100.0 - 6.0 * tint];
            // Over two texels, so that the normal map's slope at a stone's foot is a ramp, not a
            // one-texel cliff that would alias into dotted lines.
            let t = smoothstep((edge - MORTAR + 1.0) * 0.5);
            let height = mortar_height + t * (stone_height - mortar_height);
            let colour = [0, 1, 2].map(|i| mortar[i] + t * (base[i] * shade - mortar[i]));
            heights.push(height.clamp(0.0, 1.0));
            colours.push(colour.map(|c| to_u8(c / 255.0)));
        }
    }
    let height_map = HeightMap {
        width: SIZE,
        height: SIZE,
        values: heights,
    };
    let options = NormalMapOptions {
        strength: STRENGTH,
        ..Default::default()
    };
    let normals = normal_map(&height_map, options);
    let diffuse =
        encode_bmp(&colours, SIZE).map_err(|reason| write_error(FILES.diffuse, reason))?;
    let normal = encode_bmp(&normals, SIZE).map_err(|reason| write_error(FILES.normal, reason))?;
    Ok(vec![(FILES.diffuse, diffuse), (FILES.normal, normal)])
}

/// One jittered point per cell of a `STONES`² grid over the tile.
struct Stones {
    points: Vec<(f32, f32)>,
}

impl Stones {
    fn new() -> Self {
        let cell = SIZE as f32 / STONES as f32;
        let points = (0..STONES * STONES)
            .map(|i| {
                let (cx, cy) = (i % STONES, i / STONES);
                // Kept away from the cell's border, so that no stone is a sliver.
                let jx = 0.2 + 0.6 * unit(hash3(cx, cy, 1));
                let jy = 0.2 + 0.6 * unit(hash3(cx, cy, 2));
                ((cx as f32 + jx) * cell, (cy as f32 + jy) * cell)
            })
            .collect();
        Stones { points }
    }

    /// The stone at texel position (x, y) and about how far its border is: half the difference of
    /// the two nearest points' distances (exact on the line through them), wrapping around the tile.
    fn nearest(&self, x: f32, y: f32) -> (u32, f32) {
        let size = SIZE as f32;
        let wrapped = |d: f32| {
            let d = d.abs();
            d.min(size - d)
        };
        let (mut first, mut second) = ((0u32, f32::MAX), f32::MAX);
        for (i, &(px, py)) in self.points.iter().enumerate() {
            let (dx, dy) = (wrapped(x - px), wrapped(y - py));
            let d = (dx * dx + dy * dy).sqrt();
            if d < first.1 {
                second = first.1;
                first = (i as u32, d);
            } else if d < second {
                second = d;
            }
        }
        (first.0, (second - first.1) * 0.5)
    }
}
