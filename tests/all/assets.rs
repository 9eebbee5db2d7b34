//! The project's own assets: reproducible, in the tutorial's conventions, and oriented so that the
//! tutorial's shaders show raised bricks whose bumps line up with their colours.

use std::path::{Path, PathBuf};

use glam::Vec3;
use tutorial13::assets::obj_text::tutorial_cylinder_obj_text;
use tutorial13::assets::{brick_height_map, make_assets, normal_map_from_height, ASSET_FILES};

use crate::common;

const SIZE: usize = 1024;

fn committed(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The committed normal map as the image crate decodes it: RGB, picture row 0 (top) first.
fn committed_normal_map() -> image::RgbImage {
    image::open(committed("normal.bmp"))
        .expect("assets/normal.bmp decodes")
        .to_rgb8()
}

/// Level 0 of a committed DXT3 file, decoded to RGBA in file order (first stored row first).
fn committed_dds_level0(name: &str) -> Vec<u8> {
    let bytes = read(&committed(name));
    let mut rgba = vec![0u8; SIZE * SIZE * 4];
    texpresso::Format::Bc2.decompress(&bytes[128..], SIZE, SIZE, &mut rgba);
    rgba
}

fn decode_normal(p: [u8; 3]) -> Vec3 {
    // As the fragment shader does: texel * 2 - 1.
    Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) / 255.0 * 2.0 - 1.0
}

// Fails if make_assets reports success without writing into a folder it had to create.
#[test]
fn make_assets_creates_nested_folders() {
    let dir = common::scratch("nested").join("a/b");
    let files = tutorial13::scenes::generate_assets().unwrap();
    make_assets(&dir, &files, false).expect("make_assets succeeds");
    for name in ASSET_FILES {
        assert!(dir.join(name).is_file(), "{name} missing");
    }
}

// Fails if the encoding is off by half a step (flat must be exactly 128,128,255) or if a flat
// height map picks up a gradient somewhere (e.g. at the wrap-around).
#[test]
fn flat_height_gives_exactly_128_128_255() {
    let normals = normal_map_from_height(&vec![0.37; 16 * 16], 16, 14.0);
    assert!(normals.iter().all(|&p| p == [128, 128, 255]));
}

// Fails if the channel signs change: red grows with height rising to the right, green with height
// rising up the picture (towards row 0), which is what the tutorial's tangent frame needs.
#[test]
fn normal_channel_signs_follow_the_tutorials_frame() {
    let n = 8;
    let ramp_right: Vec<f32> = (0..n * n).map(|i| (i % n) as f32 * 0.01).collect();
    let ramp_up: Vec<f32> = (0..n * n).map(|i| (n - 1 - i / n) as f32 * 0.01).collect();
    // Away from the wrap-around column/row, where the ramp jumps back.
    let p = normal_map_from_height(&ramp_right, n as u32, 30.0)[3 * n + 3];
    assert!(p[0] > 150 && p[1] == 128, "ramp to the right gives {p:?}");
    let p = normal_map_from_height(&ramp_up, n as u32, 30.0)[3 * n + 3];
    assert!(p[0] == 128 && p[1] > 150, "ramp up the picture gives {p:?}");
}

// Fails if flat areas (the mortar) are not exactly (128,128,255) in normal.bmp, if a texel encodes
// a normal pointing into the surface or far from unit length, or if normal.bmp is not the map of the
// public height map.
#[test]
fn committed_normal_map_is_unit_outward_and_flat_where_the_height_is() {
    let map = committed_normal_map();
    assert_eq!(map.dimensions(), (SIZE as u32, SIZE as u32));
    let height = brick_height_map(SIZE as u32);
    let h = |col: usize, row: usize| height[(row % SIZE) * SIZE + col % SIZE];
    let mut flat = 0;
    for row in 0..SIZE {
        for col in 0..SIZE {
            let p = map.get_pixel(col as u32, row as u32).0;
            let n = decode_normal(p);
            assert!(n.z > 0.0, "texel ({col}, {row}) = {p:?} points inwards");
            assert!(
                (n.length() - 1.0).abs() <= 0.02,
                "texel ({col}, {row}) = {p:?} has length {}",
                n.length()
            );
            let level = h(col + SIZE - 1, row) == h(col + 1, row)
                && h(col, row + SIZE - 1) == h(col, row + 1);
            if level {
                flat += 1;
                assert_eq!(p, [128, 128, 255], "flat texel ({col}, {row})");
            }
        }
    }
    // The mortar covers roughly a tenth of the tile.
    assert!(flat > SIZE * SIZE / 20, "only {flat} flat texels");
}

/// Mean absolute difference between two columns (or rows) of values.
fn line_difference(a: impl Iterator<Item = f32>, b: impl Iterator<Item = f32>) -> f32 {
    let (mut sum, mut count) = (0.0, 0);
    for (x, y) in a.zip(b) {
        sum += (x - y).abs();
        count += 1;
    }
    sum / count as f32
}

// Fails if the texture shows a seam where it repeats: the last column against the first (and the
// last row against the first) must differ no more than neighbouring columns (rows) do on average,
// with some slack.
#[test]
fn height_and_normal_maps_tile() {
    let height = brick_height_map(SIZE as u32);
    let map = committed_normal_map();
    let red_green: Vec<f32> = map.pixels().map(|p| p[0] as f32 + p[1] as f32).collect();
    for (what, field) in [("height", &height), ("normal map", &red_green)] {
        let col = |c: usize| (0..SIZE).map(move |r| field[r * SIZE + c]);
        let row = |r: usize| (0..SIZE).map(move |c| field[r * SIZE + c]);
        let typical_cols = (0..SIZE - 1)
            .map(|c| line_difference(col(c), col(c + 1)))
            .sum::<f32>()
            / 1023.0;
        let typical_rows = (0..SIZE - 1)
            .map(|r| line_difference(row(r), row(r + 1)))
            .sum::<f32>()
            / 1023.0;
        let seam_cols = line_difference(col(SIZE - 1), col(0));
        let seam_rows = line_difference(row(SIZE - 1), row(0));
        assert!(
            seam_cols <= 2.0 * typical_cols,
            "{what}: columns seam {seam_cols} vs typical {typical_cols}"
        );
        assert!(
            seam_rows <= 2.0 * typical_rows,
            "{what}: rows seam {seam_rows} vs typical {typical_rows}"
        );
    }
}

struct Obj {
    positions: Vec<Vec3>,
    uvs: Vec<[f32; 2]>,
    normals: Vec<Vec3>,
    /// 0-based (position, uv, normal) per corner.
    faces: Vec<[[usize; 3]; 3]>,
}

/// A strict reader for what the tutorial's loader accepts: `v`, `vt`, `vn`, `f a/b/c a/b/c a/b/c`.
fn parse_obj(text: &str) -> Obj {
    let mut obj = Obj {
        positions: vec![],
        uvs: vec![],
        normals: vec![],
        faces: vec![],
    };
    let floats = |rest: &[&str]| -> Vec<f32> {
        rest.iter()
            .map(|s| s.parse().unwrap_or_else(|_| panic!("not a number: {s}")))
            .collect()
    };
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.first().copied() {
            Some("v") => {
                let f = floats(&words[1..]);
                assert_eq!(f.len(), 3, "{line}");
                obj.positions.push(Vec3::new(f[0], f[1], f[2]));
            }
            Some("vt") => {
                let f = floats(&words[1..]);
                assert_eq!(f.len(), 2, "{line}");
                obj.uvs.push([f[0], f[1]]);
            }
            Some("vn") => {
                let f = floats(&words[1..]);
                assert_eq!(f.len(), 3, "{line}");
                obj.normals.push(Vec3::new(f[0], f[1], f[2]));
            }
            Some("f") => {
                assert_eq!(words.len(), 4, "not a triangle: {line}");
                let corner = |w: &str| -> [usize; 3] {
                    let idx: Vec<usize> = w
                        .split('/')
                        .map(|s| s.parse().unwrap_or_else(|_| panic!("not a/b/c: {line}")))
                        .collect();
                    assert_eq!(idx.len(), 3, "not a/b/c: {line}");
                    [idx[0] - 1, idx[1] - 1, idx[2] - 1]
                };
                obj.faces
                    .push([corner(words[1]), corner(words[2]), corner(words[3])]);
            }
            _ => {}
        }
    }
    for f in &obj.faces {
        for c in f {
            assert!(c[0] < obj.positions.len() && c[1] < obj.uvs.len() && c[2] < obj.normals.len());
        }
    }
    obj
}

// Fails if the cylinder loses the tutorial's layout: counts (64 positions, 66 UVs with the seam
// duplicates, 32 normals, 64 triangles), radius 1, y in [0, 2], radial normals, V 0 at the bottom
// and 1 at the top, or a face wound clockwise seen from outside (it would be culled).
#[test]
fn cylinder_has_the_tutorials_shape_and_winding() {
    let obj = parse_obj(&tutorial_cylinder_obj_text(32));
    assert_eq!(obj.positions.len(), 64);
    assert_eq!(obj.uvs.len(), 66);
    assert_eq!(obj.normals.len(), 32);
    assert_eq!(obj.faces.len(), 64);
    for p in &obj.positions {
        assert!(
            (p.x.hypot(p.z) - 1.0).abs() < 1e-5,
            "{p} is not at radius 1"
        );
        assert!(p.y == 0.0 || p.y == 2.0, "{p} is not on a rim");
    }
    for n in &obj.normals {
        assert!(
            (n.length() - 1.0).abs() < 1e-5 && n.y == 0.0,
            "{n} is not radial"
        );
    }
    for f in &obj.faces {
        let [a, b, c] = f.map(|corner| obj.positions[corner[0]]);
        let face_normal = (b - a).cross(c - a);
        let centre = (a + b + c) / 3.0;
        let outward = Vec3::new(centre.x, 0.0, centre.z);
        assert!(
            face_normal.dot(outward) > 0.0,
            "face {f:?} is clockwise from outside"
        );
        for corner in f {
            assert!(face_normal.dot(obj.normals[corner[2]]) > 0.0);
            let (p, uv) = (obj.positions[corner[0]], obj.uvs[corner[1]]);
            assert_eq!(uv[1], p.y / 2.0, "V must run 0 (bottom) to 1 (top)");
        }
        // No face spans the whole texture (the seam has its own UVs).
        let us = f.map(|corner| obj.uvs[corner[1]][0]);
        let span = us.iter().cloned().fold(f32::MIN, f32::max)
            - us.iter().cloned().fold(f32::MAX, f32::min);
        assert!(span < 0.2, "face {f:?} spans {span} in U");
    }
}

// Fails if the UVs stop matching the tutorial's (range about -1.36..2.36, U falling as the ring
// angle grows, V up) or its winding and V orientation convention; skipped without the tutorial's files.
#[test]
fn cylinder_matches_the_tutorials_conventions() {
    let Some(original) = common::original_assets("cylinder_matches_the_tutorials_conventions")
    else {
        return;
    };
    let text = String::from_utf8(read(&original.join("cylinder.obj"))).expect("UTF-8");
    let theirs = parse_obj(&text);
    let ours = parse_obj(&tutorial_cylinder_obj_text(32));
    let u_range = |obj: &Obj| {
        let us = obj.uvs.iter().map(|uv| uv[0]);
        (
            us.clone().fold(f32::MAX, f32::min),
            us.fold(f32::MIN, f32::max),
        )
    };
    let (ours_u, theirs_u) = (u_range(&ours), u_range(&theirs));
    assert!((ours_u.0 - theirs_u.0).abs() < 0.01 && (ours_u.1 - theirs_u.1).abs() < 0.01);
    // Per face: the sign of the UV-space area (i.e. whether the UVs are mirrored against the
    // outward winding) and which way V runs along y.
    let conventions = |obj: &Obj| {
        obj.faces
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|corner| obj.uvs[corner[1]]);
                let uv_area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
                let v_up = f.iter().all(|corner| {
                    (obj.uvs[corner[1]][1] > 0.5) == (obj.positions[corner[0]].y > 1.0)
                });
                (uv_area > 0.0, v_up)
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(conventions(&ours), conventions(&theirs));
    // Same positions in the same order (the tutorial's ring starts at -Z and turns towards +X).
    for (p, q) in ours.positions.iter().zip(&theirs.positions) {
        assert!(p.distance(*q) < 1e-4, "{p} vs {q}");
    }
}

// Fails if a DDS file stops being what the tutorial's loader expects: DXT3, 1024², 11 mip levels,
// data exactly the sum of the level sizes.
#[test]
fn dds_headers_and_lengths() {
    for name in ["diffuse.DDS", "specular.DDS"] {
        let bytes = read(&committed(name));
        let dds = ddsfile::Dds::read(&bytes[..]).expect("DDS parses");
        assert_eq!(
            dds.get_d3d_format(),
            Some(ddsfile::D3DFormat::DXT3),
            "{name}"
        );
        assert_eq!((dds.get_width(), dds.get_height()), (1024, 1024), "{name}");
        assert_eq!(dds.get_num_mipmap_levels(), 11, "{name}");
        let levels: usize = (0..11)
            .map(|level| {
                let side = (SIZE >> level).max(1);
                side.div_ceil(4) * side.div_ceil(4) * 16
            })
            .sum();
        assert_eq!(bytes.len(), 128 + levels, "{name}");
    }
}

// Fails if the header differs from the tutorial's (flags, linear size, mip count, caps), which the
// tutorial's loader and other DDS readers rely on; skipped without the tutorial's files.
#[test]
fn dds_header_is_byte_identical_to_the_tutorials() {
    let Some(original) = common::original_assets("dds_header_is_byte_identical_to_the_tutorials")
    else {
        return;
    };
    let theirs = read(&original.join("diffuse.DDS"));
    for name in ["diffuse.DDS", "specular.DDS"] {
        let ours = read(&committed(name));
        assert_eq!(ours[..128], theirs[..128], "{name}");
    }
}

// Fails if the mip levels are out of order or not filtered from level 0: the 1×1 level must be
// the mean colour of level 0.
#[test]
fn last_mip_level_is_the_mean_colour() {
    for name in ["diffuse.DDS", "specular.DDS"] {
        let bytes = read(&committed(name));
        let level0 = committed_dds_level0(name);
        let last = texpresso::Format::Bc2.decompress_block(&bytes[bytes.len() - 16..])[0];
        for (k, &last) in last.iter().take(3).enumerate() {
            let mean = level0
                .iter()
                .skip(k)
                .step_by(4)
                .map(|&c| c as f32)
                .sum::<f32>()
                / (SIZE * SIZE) as f32;
            assert!(
                (mean - last as f32).abs() <= 8.0,
                "{name} channel {k}: mean {mean}, 1×1 level {last}"
            );
        }
    }
}

// Fails if the DDS textures are stored the other way up from the normal map: with the tutorial's
// sampling (DDS at V negated, BMP at V), DDS row r and BMP picture row r land on the same spot, so
// the mortar (flat in the normal map) must be where the specular map is black and the diffuse map
// is dark. (Turned upside down, the running bond puts half the joints on bricks.)
#[test]
fn dds_mortar_lines_up_with_flat_normals() {
    let normals = committed_normal_map();
    let specular = committed_dds_level0("specular.DDS");
    let diffuse = committed_dds_level0("diffuse.DDS");
    // Fraction of the flat texels where the DDS texel (row flipped or not) is mortar-dark: ~0.98
    // (DXT blocks blur the mortar's edge), ~0.7 upside down.
    let mortar_match = |flip: bool| {
        let (mut flat, mut specular_dark, mut diffuse_dark) = (0usize, 0usize, 0usize);
        for row in 0..SIZE {
            let dds_row = if flip { SIZE - 1 - row } else { row };
            for col in 0..SIZE {
                if normals.get_pixel(col as u32, row as u32).0 != [128, 128, 255] {
                    continue;
                }
                let i = (dds_row * SIZE + col) * 4;
                flat += 1;
                specular_dark += usize::from(specular[i] < 16);
                diffuse_dark += usize::from(diffuse[i..i + 3].iter().all(|&c| c < 80));
            }
        }
        (
            specular_dark as f64 / flat as f64,
            diffuse_dark as f64 / flat as f64,
        )
    };
    let (aligned, flipped) = (mortar_match(false), mortar_match(true));
    assert!(
        aligned.0 > 0.95 && aligned.1 > 0.95,
        "mortar matches only (specular, diffuse) = {aligned:?}"
    );
    assert!(
        flipped.0 < 0.85 && flipped.1 < 0.85,
        "the check cannot tell: {flipped:?} upside down"
    );
}

// Fails if bricks would look sunken (or lit from the wrong side) under the tutorial's shader: with
// the crate's own loader and tangent code, a texel where the height falls towards the top of the
// picture must have a world normal tilted up, and one where it falls towards the left, tilted
// towards the picture's left (-U). Checked at the front of the cylinder, which faces the camera.
#[test]
fn bricks_look_raised_with_the_tutorials_tangent_frame() {
    let obj = tutorial_cylinder_obj_text(32);
    let soup = tutorial13::pipeline::obj_parse::load_obj_bytes_threaded(
        obj.as_bytes(),
        Path::new("cylinder.obj"),
    )
    .expect("cylinder loads");
    let basis = tutorial13::common::tangentspace::compute_tangent_basis(&soup, Default::default());
    let front = (0..soup.vertices.len())
        .max_by(|&a, &b| soup.vertices[a].z.total_cmp(&soup.vertices[b].z))
        .expect("corners");
    let (t, b, n) = (
        basis.tangents[front].normalize(),
        basis.bitangents[front].normalize(),
        soup.normals[front],
    );
    // At the front (0, y, 1), U grows towards +X and V towards +Y: the picture's right and up.
    let (right, up) = (Vec3::X, Vec3::Y);

    let height = brick_height_map(SIZE as u32);
    let h = |col: usize, row: usize| height[(row % SIZE) * SIZE + col % SIZE];
    let map = committed_normal_map();
    let (mut checked, mut wrong) = (0, 0);
    for row in 0..SIZE {
        for col in 0..SIZE {
            let dh_right = h(col + 1, row) - h(col + SIZE - 1, row);
            let dh_up = h(col, row + SIZE - 1) - h(col, row + 1);
            if dh_right.abs().max(dh_up.abs()) < 0.05 {
                continue;
            }
            let nt = decode_normal(map.get_pixel(col as u32, row as u32).0);
            let world = nt.x * t + nt.y * b + nt.z * n;
            checked += 1;
            for (slope, axis) in [(dh_right, right), (dh_up, up)] {
                if slope.abs() >= 0.05 && slope * world.dot(axis) >= 0.0 {
                    wrong += 1;
                }
            }
        }
    }
    assert!(checked > 10_000, "only {checked} steep texels");
    assert!(
        wrong * 1000 < checked,
        "{wrong} of {checked} steep texels tilt the wrong way"
    );
}
