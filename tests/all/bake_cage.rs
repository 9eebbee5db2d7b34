//! `tutorial13 bake --cage` and `--match-names`: a cage's rays start at its point and go toward
//! LOW's, measured against an exact case (planes at known heights, a cage with known corners); parts
//! matched by name keep a LOW part's rays on its own HIGH part; a bad cage or names that pair with
//! nothing are one line with nothing written.

use std::fmt::Write;
use std::path::Path;

use glam::{DVec3, Vec3};
use tutorial13::model::{load_model, MapOverrides};

use crate::bake::{assert_refused, bake_cli, decode};
use crate::common::{scratch, text};

/// LOW's cells per side: a grid over [0, 1]² at z = 0, UV = (x, y), two triangles a cell.
const CELLS: usize = 6;
/// The maps' side.
const SIZE: usize = 64;
/// HIGH's strips: a ridge of planes across x from -0.5 by this width, constant along y.
const STRIP: f64 = 0.025;
const STRIPS: usize = 80;

/// A value in [0, 1) for two whole numbers (the usual sine hash): the fixtures' irregularity.
fn hash(a: usize, b: usize) -> f64 {
    let s = (a as f64 * 12.9898 + b as f64 * 78.233).sin() * 43758.5453;
    s - s.floor()
}

/// LOW's vertex (i, j).
fn low_vertex(i: usize, j: usize) -> DVec3 {
    DVec3::new(i as f64, j as f64, 0.0) / CELLS as f64
}

/// The cage's vertex (i, j): LOW's, raised by 0.1 to 0.25 and slid up to 0.06 along x and y, so
/// that its rays run slanted, each cell's differently.
fn cage_vertex(i: usize, j: usize) -> DVec3 {
    let slide = DVec3::new(hash(i, j) - 0.5, hash(j + 7, i) - 0.5, 0.0) * 0.12;
    low_vertex(i, j) + slide + DVec3::Z * (0.1 + 0.15 * hash(i + 3, j + 11))
}

/// The grid as an OBJ: `vertex` places (i, j); rows of cells alternate between materials A and B
/// (with `materials`, so that the reader groups A's rows before B's); corners `v/vt/vn` with
/// `uvs`, `v//vn` without.
fn grid_obj(vertex: impl Fn(usize, usize) -> DVec3, materials: bool, uvs: bool) -> String {
    let mut obj = String::from("# Blender 4.2.0\n");
    if materials {
        obj.push_str("mtllib low.mtl\n");
    }
    for j in 0..=CELLS {
        for i in 0..=CELLS {
            let p = vertex(i, j);
            writeln!(obj, "v {:.6} {:.6} {:.6}", p.x, p.y, p.z).unwrap();
        }
    }
    if uvs {
        for j in 0..=CELLS {
            for i in 0..=CELLS {
                let uv = low_vertex(i, j);
                writeln!(obj, "vt {:.6} {:.6}", uv.x, uv.y).unwrap();
            }
        }
    }
    obj.push_str("vn 0 0 1\ns 0\n");
    let index = |i: usize, j: usize| j * (CELLS + 1) + i + 1;
    let corner = |k: usize| match uvs {
        true => format!("{k}/{k}/1"),
        false => format!("{k}//1"),
    };
    for j in 0..CELLS {
        if materials {
            obj.push_str(if j % 2 == 0 {
                "usemtl A\n"
            } else {
                "usemtl B\n"
            });
        }
        for i in 0..CELLS {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            let mut face = |k: [usize; 3]| {
                let [x, y, z] = k.map(corner);
                writeln!(obj, "f {x} {y} {z}").unwrap();
            };
            face([a, b, c]);
            face([a, c, d]);
        }
    }
    obj
}

/// Where the cage is above LOW's point (u, v, 0): the cage's corners mixed with the point's
/// barycentrics in its triangle of the grid (the lower one below the cell's diagonal).
fn cage_point(u: f64, v: f64) -> DVec3 {
    let n = CELLS as f64;
    let (i, j) = (
        ((u * n) as usize).min(CELLS - 1),
        ((v * n) as usize).min(CELLS - 1),
    );
    let (fu, fv) = (u * n - i as f64, v * n - j as f64);
    if fu >= fv {
        cage_vertex(i, j) * (1.0 - fu)
            + cage_vertex(i + 1, j) * (fu - fv)
            + cage_vertex(i + 1, j + 1) * fv
    } else {
        cage_vertex(i, j) * (1.0 - fv)
            + cage_vertex(i + 1, j + 1) * fu
            + cage_vertex(i, j + 1) * (fv - fu)
    }
}

/// HIGH's ridge: the height at strip edge k, from -0.3 to -0.1: detail deep below LOW, where a
/// slanted ray lands far from the point below LOW's.
fn ridge_height(k: usize) -> f64 {
    -0.3 + 0.2 * hash(k, 1)
}

fn ridge_x(k: usize) -> f64 {
    -0.5 + k as f64 * STRIP
}

/// Strip k's normal: the plane's, tilted against its slope.
fn strip_normal(k: usize) -> DVec3 {
    let slope = (ridge_height(k + 1) - ridge_height(k)) / STRIP;
    DVec3::new(-slope, 0.0, 1.0).normalize()
}

/// HIGH: the ridge's strips from y = -0.5 to 1.5, each strip's normal at its corners (sharp
/// edges between strips).
fn ridge_obj() -> String {
    let mut obj = String::from("# Blender 4.2.0\nvt 0 0\n");
    for k in 0..STRIPS {
        let n = strip_normal(k);
        writeln!(obj, "vn {:.8} {:.8} {:.8}", n.x, n.y, n.z).unwrap();
    }
    for k in 0..=STRIPS {
        for y in [-0.5, 1.5] {
            writeln!(obj, "v {:.6} {y} {:.6}", ridge_x(k), ridge_height(k)).unwrap();
        }
    }
    for k in 0..STRIPS {
        let (a, b, c, d) = (2 * k + 1, 2 * k + 3, 2 * k + 4, 2 * k + 2);
        let n = k + 1;
        writeln!(
            obj,
            "f {a}/1/{n} {b}/1/{n} {c}/1/{n}\nf {a}/1/{n} {c}/1/{n} {d}/1/{n}"
        )
        .unwrap();
    }
    obj
}

/// The ray from the cage's `c` toward LOW's `p` and on: the distance from `c` to its first strip,
/// that strip, and how far the hit is from the strip's edges (in x).
fn first_strip(c: DVec3, p: DVec3) -> Option<(f64, usize, f64)> {
    let d = (p - c).normalize();
    let mut best: Option<(f64, usize, f64)> = None;
    for k in 0..STRIPS {
        let (x0, z0) = (ridge_x(k), ridge_height(k));
        let slope = (ridge_height(k + 1) - z0) / STRIP;
        // c.z + t d.z = z0 + slope (c.x + t d.x - x0)
        let t = (z0 + slope * (c.x - x0) - c.z) / (d.z - slope * d.x);
        let x = c.x + t * d.x;
        if t >= 0.0 && (x0..=x0 + STRIP).contains(&x) && best.is_none_or(|b| t < b.0) {
            best = Some((t, k, (x - x0).min(x0 + STRIP - x)));
        }
    }
    best
}

/// The angle between two vectors in degrees, to well under 0.001° (f32 vectors 0.01° apart have a
/// dot product within rounding of 1, where acos cannot tell).
fn degrees(a: Vec3, b: Vec3) -> f64 {
    let (a, b) = (a.as_dvec3(), b.as_dvec3());
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// The number before " rays" in the report's line of misses (0 where every ray met HIGH).
fn missed_rays(stdout: &str) -> usize {
    stdout
        .lines()
        .find(|l| l.contains("met nothing"))
        .map_or(0, |l| l.split(' ').next().unwrap().parse().unwrap())
}

// Fails if a ray does not start at the cage's point for its texel (its triangle and barycentrics
// on the cage, paired with LOW's by the files' face order though LOW's reader groups its
// materials), does not go toward LOW's point and on past it, takes a hit other than the first,
// or measures --max-distance from elsewhere than the cage: every texel's normal must be the
// strip the exact ray meets within 0.01°, the flat normal where the bound stops it first, and the
// misses counted so. Texels whose exact hit lies within 1e-4 of a strip's edge or of the bound are
// left out (f32 decides those), at most 5 %.
#[test]
fn a_cage_sends_each_ray_from_its_point_toward_lows() {
    let dir = scratch("exact");
    std::fs::write(dir.join("low.obj"), grid_obj(low_vertex, true, true)).unwrap();
    std::fs::write(
        dir.join("low.mtl"),
        "newmtl A\nKd 1 0 0\nnewmtl B\nKd 0 1 0\n",
    )
    .unwrap();
    std::fs::write(dir.join("cage.obj"), grid_obj(cage_vertex, false, false)).unwrap();
    std::fs::write(dir.join("high.obj"), ridge_obj()).unwrap();
    let low = load_model(&dir.join("low.obj"), &MapOverrides::default()).unwrap();
    assert!(
        !low.file_order.is_empty(),
        "LOW's triangles should be regrouped by material, its soup order not the file's"
    );
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (high, low, cage) = (path("high.obj"), path("low.obj"), path("cage.obj"));
    let (mut below_low, mut below_cage) = (0, 0);
    for bound in [None, Some(0.4)] {
        let out = path("map.png");
        let mut args = vec![
            high.as_str(),
            low.as_str(),
            "--cage",
            cage.as_str(),
            "-o",
            out.as_str(),
            "--size",
            "64",
            "--depth",
            "16",
            "--margin",
            "0",
        ];
        let bound_text = bound.map(|b: f64| b.to_string());
        if let Some(b) = &bound_text {
            args.extend(["--max-distance", b.as_str()]);
        }
        let output = bake_cli(&args);
        let stdout = text(&output.stdout);
        assert!(output.status.success(), "{}", text(&output.stderr));
        let (_, _, baked) = decode(Path::new(&out));
        let (mut worst, mut checked, mut misses, mut undecided) = (0f64, 0, 0, 0);
        for (texel, n) in baked.iter().enumerate() {
            let (x, y) = (texel % SIZE, texel / SIZE);
            let (u, v) = (
                (x as f64 + 0.5) / SIZE as f64,
                1.0 - (y as f64 + 0.5) / SIZE as f64,
            );
            let (c, p) = (cage_point(u, v), DVec3::new(u, v, 0.0));
            let (t, k, edge) = first_strip(c, p).expect("the ridge spans every ray");
            let beyond = bound.is_some_and(|b| t > b);
            if edge < 1e-4 || bound.is_some_and(|b| (t - b).abs() < 1e-4) {
                undecided += 1;
                continue;
            }
            if bound.is_none() {
                let down = |from: DVec3| first_strip(from, from - DVec3::Z).unwrap().1;
                below_low += usize::from(down(p + DVec3::Z) != k);
                below_cage += usize::from(down(c) != k);
            }
            let expected = match beyond {
                true => Vec3::Z,
                false => strip_normal(k).as_vec3(),
            };
            misses += usize::from(beyond);
            worst = worst.max(degrees(*n, expected));
            checked += 1;
        }
        let label = format!("--max-distance {bound:?}");
        assert!(worst < 0.01, "{label}: a texel {worst}° off");
        assert!(
            undecided * 20 <= SIZE * SIZE,
            "{label}: {undecided} undecided"
        );
        let reported = missed_rays(&stdout);
        assert!(
            reported >= misses && reported <= misses + undecided,
            "{label}: {reported} misses reported, {misses} certain and {undecided} undecided: {stdout}"
        );
        assert!(checked > 0);
    }
    // The cage's slant decides the strip: straight down from LOW's point, or from the cage's,
    // meets another at most texels, so a ray along LOW's normal from either would fail the test.
    assert!(
        below_low * 2 > SIZE * SIZE && below_cage * 2 > SIZE * SIZE,
        "only {below_low} and {below_cage} texels meet another strip than the one below LOW's \
         point and the cage's"
    );
}

// Fails if a cage with other faces (one fewer, or one cell's diagonal turned), a cage with a NaN,
// a missing cage, --cage with --extrusion, or names that pair with nothing is taken, panics, says
// more or less than one line naming the file and the reason, or writes anything.
#[test]
fn a_bad_cage_or_names_that_pair_nothing_are_one_line() {
    let dir = scratch("bad");
    let write = |name: &str, contents: &str| {
        let path = dir.join(name);
        std::fs::write(&path, contents).unwrap();
        path.to_str().unwrap().to_string()
    };
    let low = write("low.obj", &grid_obj(low_vertex, false, true));
    let high = write("high.obj", &ridge_obj());
    let cage = grid_obj(cage_vertex, false, false);
    let last_face = cage.rfind("\nf ").unwrap();
    let fewer = write("cage-fewer.obj", &cage[..last_face + 1]);
    // Cell (0, 0) cut along its other diagonal: as many triangles, other corners.
    let turned = write(
        "cage-turned.obj",
        &cage.replacen(
            "f 1//1 2//1 9//1\nf 1//1 9//1 8//1\n",
            "f 1//1 2//1 8//1\nf 2//1 9//1 8//1\n",
            1,
        ),
    );
    assert_ne!(turned, fewer);
    let first_vertex = cage.lines().find(|l| l.starts_with("v ")).unwrap();
    let nan = write(
        "cage-nan.obj",
        &cage.replacen(first_vertex, "v nan 0 0.2", 1),
    );
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    let out = out_dir.join("map.png");
    let out = out.to_str().unwrap();
    let missing = dir.join("no-cage.obj");
    let missing = missing.to_str().unwrap();
    let cases: [(&[&str], &str); 6] = [
        (
            &["--cage", &fewer],
            "cage-fewer.obj: not a cage for LOW: 71 triangles where LOW",
        ),
        (
            &["--cage", &turned],
            "cage-turned.obj: not a cage for LOW: its triangles",
        ),
        (&["--cage", &nan], "cage-nan.obj"),
        (&["--cage", missing], "no-cage.obj"),
        (&["--cage", &turned, "--extrusion", "0.1"], "--extrusion"),
        (&["--match-names"], "--match-names: no part's name pairs"),
    ];
    for (flags, reason) in cases {
        let mut args = vec![high.as_str(), low.as_str(), "-o", out, "--size", "16"];
        args.extend(flags);
        assert_refused(&args, reason, &out_dir);
    }
}

/// One named part of the matched-names pair: flat triangles, one normal, UVs (u, v) of each corner.
struct Part {
    name: &'static str,
    /// The glTF's node has no name, only its mesh.
    mesh_name_only: bool,
    corners: Vec<DVec3>,
    uvs: Vec<[f64; 2]>,
    normal: DVec3,
}

/// A rectangle over x0..x1, y0..y1 on the plane z = z0 + sx (x - x0) + sy (y - y0), its UVs
/// `uv(x, y)`.
fn plate(
    name: &'static str,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    (z0, sx, sy): (f64, f64, f64),
    uv: impl Fn(f64, f64) -> [f64; 2],
) -> Part {
    let at = |x: f64, y: f64| DVec3::new(x, y, z0 + sx * (x - x0) + sy * (y - y0));
    let square = [(x0, y0), (x1, y0), (x1, y1), (x0, y0), (x1, y1), (x0, y1)];
    Part {
        name,
        mesh_name_only: false,
        corners: square.iter().map(|&(x, y)| at(x, y)).collect(),
        uvs: square.iter().map(|&(x, y)| uv(x, y)).collect(),
        normal: DVec3::new(-sx, -sy, 1.0).normalize(),
    }
}

/// The parts as an OBJ, each under `keyword` (o or g) and its name.
fn parts_obj(parts: &[Part], keyword: &str) -> String {
    let mut obj = String::from("# Blender 4.2.0\n");
    let mut first = 1;
    for part in parts {
        writeln!(obj, "{keyword} {}", part.name).unwrap();
        let n = part.normal;
        writeln!(obj, "vn {:.8} {:.8} {:.8}", n.x, n.y, n.z).unwrap();
        for (p, uv) in part.corners.iter().zip(&part.uvs) {
            writeln!(obj, "v {} {} {}\nvt {} {}", p.x, p.y, p.z, uv[0], uv[1]).unwrap();
        }
        for t in 0..part.corners.len() / 3 {
            let k = first + 3 * t;
            writeln!(
                obj,
                "f {k}/{k}/-1 {}/{}/-1 {}/{}/-1",
                k + 1,
                k + 1,
                k + 2,
                k + 2
            )
            .unwrap();
        }
        first += part.corners.len();
    }
    obj
}

/// The parts as a binary glTF: a node and a mesh for each, the node named (or only its mesh).
fn parts_glb(parts: &[Part]) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let (mut nodes, mut meshes, mut accessors, mut views) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut add =
        |bin: &mut Vec<u8>, values: Vec<f32>, kind: &str, count: usize, bounds: String| {
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
                bin.len(),
                4 * values.len()
            ));
            values.iter().for_each(|v| bin.extend(v.to_le_bytes()));
            accessors.push(format!(
            r#"{{"bufferView":{},"componentType":5126,"count":{count},"type":"{kind}"{bounds}}}"#,
            views.len() - 1
        ));
            accessors.len() - 1
        };
    for (m, part) in parts.iter().enumerate() {
        let count = part.corners.len();
        let positions: Vec<f32> = part
            .corners
            .iter()
            .flat_map(|p| p.as_vec3().to_array())
            .collect();
        let (lo, hi) = part.corners.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(p.as_vec3()), hi.max(p.as_vec3())),
        );
        let bounds = format!(r#","min":{:?},"max":{:?}"#, lo.to_array(), hi.to_array());
        let position = add(&mut bin, positions, "VEC3", count, bounds);
        let normals = (0..count)
            .flat_map(|_| part.normal.as_vec3().to_array())
            .collect();
        let normal = add(&mut bin, normals, "VEC3", count, String::new());
        // glTF's V runs down the picture.
        let uvs = part
            .uvs
            .iter()
            .flat_map(|uv| [uv[0] as f32, 1.0 - uv[1] as f32])
            .collect();
        let uv = add(&mut bin, uvs, "VEC2", count, String::new());
        meshes.push(format!(
            r#"{{"name":"{}","primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal},"TEXCOORD_0":{uv}}}}}]}}"#,
            if part.mesh_name_only { part.name } else { "Plane.001" }
        ));
        nodes.push(match part.mesh_name_only {
            true => format!(r#"{{"mesh":{m}}}"#),
            false => format!(r#"{{"mesh":{m},"name":"{}"}}"#, part.name),
        });
    }
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":{:?}}}],"nodes":[{}],"meshes":[{}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}}"#,
        (0..parts.len()).collect::<Vec<_>>(),
        nodes.join(","),
        meshes.join(","),
        accessors.join(","),
        views.join(","),
        bin.len()
    );
    crate::gltf::glb(&json, &bin)
}

/// LOW: parts a and b side by side at z = 0 (a over x 0..1, b over 1.2..2.2, both y 0..1), and d
/// apart, their UVs side by side.
fn named_low() -> Vec<Part> {
    vec![
        plate("a_low", (0.0, 1.0), (0.0, 1.0), (0.0, 0.0, 0.0), |x, y| {
            [0.02 + 0.3 * x, 0.02 + 0.96 * y]
        }),
        plate("b_LOW", (1.2, 2.2), (0.0, 1.0), (0.0, 0.0, 0.0), |x, y| {
            [0.35 + 0.3 * (x - 1.2), 0.02 + 0.96 * y]
        }),
        plate("d_low", (3.0, 3.2), (0.0, 0.2), (0.0, 0.0, 0.0), |x, y| {
            [0.7 + 1.25 * (x - 3.0), 0.02 + 1.25 * y]
        }),
    ]
}

/// HIGH: a's plane tilted along y; b's tilted along x, with a lip that hangs over a's right part
/// (x 0.6..1.15) between a's cage and a's plane; and c, a stray plate over a's left part
/// (x 0..0.3), tilted along x the other way, which pairs with nothing.
fn named_high() -> Vec<Part> {
    let uv = |_: f64, _: f64| [0.0, 0.0];
    let mut c = plate("c_high", (0.0, 0.3), (-0.1, 1.1), (0.06, 0.05, 0.0), uv);
    c.mesh_name_only = true;
    let mut b = plate("b_HP", (1.1, 2.3), (-0.1, 1.1), (-0.06, 0.1, 0.0), uv);
    // The lip: b's plane raised (its normal b's), 0.04 to 0.095 over a's, a's plane below 0.03.
    let lip = plate("b_HP", (0.6, 1.15), (-0.1, 1.1), (0.04, 0.1, 0.0), uv);
    b.corners.extend(lip.corners);
    b.uvs.extend(lip.uvs);
    vec![
        plate("A_high", (-0.1, 1.1), (-0.1, 1.1), (-0.08, 0.0, 0.1), uv),
        b,
        c,
    ]
}

// Fails if a LOW part's rays meet another HIGH part than the one its name pairs it with (a's texels
// under b's lip or c's plate must keep a's plane's normal, within 0.01°, where without the flag they
// take the lip's and c's: that is checked too), if b's texels do not get b's plane, if a part
// without a partner is not flat, or if the pairs and the parts left over are not said. Run with
// LOW as an OBJ (objects) and HIGH as a glTF (named nodes, and a mesh named where its node is not),
// then LOW as a glTF and HIGH as an OBJ (groups).
#[test]
fn parts_matched_by_name_meet_only_their_partner() {
    let dir = scratch("names");
    let (low, high) = (named_low(), named_high());
    std::fs::write(dir.join("low.obj"), parts_obj(&low, "o")).unwrap();
    std::fs::write(dir.join("low.glb"), parts_glb(&low)).unwrap();
    std::fs::write(dir.join("high.obj"), parts_obj(&high, "g")).unwrap();
    std::fs::write(dir.join("high.glb"), parts_glb(&high)).unwrap();
    // LOW's frame is the identity (UV along x and y, normal +z): a tangent-space texel is HIGH's
    // normal as it is.
    let (a_normal, b_normal) = (high[0].normal.as_vec3(), high[1].normal.as_vec3());
    let c_normal = high[2].normal.as_vec3();
    for (low_file, high_file) in [("low.obj", "high.glb"), ("low.glb", "high.obj")] {
        let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
        let bake = |name: &str, flag: Option<&str>| {
            let (h, l, out) = (path(high_file), path(low_file), path(name));
            let mut args = vec![h.as_str(), l.as_str(), "-o", out.as_str(), "--size", "64"];
            args.extend(["--depth", "16", "--margin", "0", "--extrusion", "0.1"]);
            args.extend(["--max-distance", "0.3"]);
            args.extend(flag);
            let output = bake_cli(&args);
            assert!(output.status.success(), "{}", text(&output.stderr));
            let (_, _, map) = decode(Path::new(&out));
            (map, text(&output.stdout), text(&output.stderr))
        };
        let (matched, stdout, stderr) = bake("matched.png", Some("--match-names"));
        let (plain, ..) = bake("plain.png", None);
        let label = format!("{low_file} and {high_file}");
        for pair in [
            "paired LOW's 'a_low' (2 triangles) with HIGH's 'A_high' (2 triangles)",
            "paired LOW's 'b_LOW' (2 triangles) with HIGH's 'b_HP' (4 triangles)",
        ] {
            assert!(stdout.contains(pair), "{label}: {stdout}");
        }
        for notice in [
            "LOW's 'd_low' (2 triangles) pairs with no part of HIGH: its texels get the flat normal",
            "HIGH's 'c_high' (2 triangles) pairs with no part of LOW: no ray meets it",
        ] {
            assert!(stderr.contains(notice), "{label}: {stderr}");
        }
        assert!(stdout.contains("every ray met HIGH"), "{label}: {stdout}");
        let (mut worst, mut bled, mut counted) = (0f64, 0, [0; 3]);
        for (texel, n) in matched.iter().enumerate() {
            let (x, y) = (texel % SIZE, texel / SIZE);
            let u = (x as f64 + 0.5) / SIZE as f64;
            let v = 1.0 - (y as f64 + 0.5) / SIZE as f64;
            // Texels a texel or more inside an island, and away from the plates' edges.
            let inside = |lo: f64, hi: f64| u > lo + 1.5 / 64.0 && u < hi - 1.5 / 64.0;
            if !(0.045..0.955).contains(&v) {
                continue;
            }
            let (part, expected, unmatched) = if inside(0.02, 0.32) {
                let x = (u - 0.02) / 0.3;
                let near = |edge: f64| (x - edge).abs() < 0.05;
                if near(0.3) || near(0.6) {
                    continue;
                }
                let bleed = match x {
                    x if x < 0.3 => Some(c_normal),
                    x if x > 0.6 => Some(b_normal),
                    _ => None,
                };
                (0, a_normal, bleed)
            } else if inside(0.35, 0.65) {
                (1, b_normal, None)
            } else if inside(0.7, 0.95) && v < 0.245 {
                (2, Vec3::Z, None)
            } else {
                continue;
            };
            counted[part] += 1;
            worst = worst.max(degrees(*n, expected));
            if let Some(bleed) = unmatched {
                // Without the flag the lip and the stray plate come first.
                assert!(
                    degrees(plain[texel], bleed) < 0.01,
                    "{label}: texel {texel}"
                );
                bled += 1;
            }
        }
        assert!(
            worst < 0.01,
            "{label}: a texel {worst}° off its part's normal"
        );
        assert!(counted.iter().all(|&c| c > 20), "{label}: {counted:?}");
        assert!(
            bled > 300,
            "{label}: only {bled} texels under the other parts"
        );
    }
}
