//! `tutorial13 bake`: a model baked onto itself is flat, a fine sphere baked onto a 32×16 UV sphere
//! gives the sphere's exact normals back through MikkTSpace's rule, mirrored UVs give both halves
//! right, the margin and the misses are what they say, the tutorial's frame is said to be skewed,
//! and bad input is one line with nothing written.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3};
use tutorial13::assets::obj_text::{bumps, relief_point, round, sphere_obj_text, Relief};
use tutorial13::bake::{BakeFiles, BakeSettings, BakedMap, Space, TexelState};
use tutorial13::model::{load_model, MapOverrides};
use tutorial13::tangent_source::TangentSource;

use crate::common::{run, scratch, text, tutorial13, without_uvs};

/// HIGH's segments and rings: fine enough that its interpolated normals are the relief's within a
/// few hundredths of a degree.
const HIGH: (u32, u32) = (384, 192);

/// A UV sphere (Blender's layout) written as `name` in `dir`.
fn sphere(
    dir: &Path,
    name: &str,
    segments: u32,
    rings: u32,
    relief: &Relief,
    mirror: bool,
) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, sphere_obj_text(segments, rings, relief, mirror)).unwrap();
    path
}

pub(crate) fn bake_cli(args: &[&str]) -> std::process::Output {
    run(tutorial13().arg("bake").args(args))
}

/// A PNG's texels as unit vectors (8 or 16 bits), row 0 at the top.
pub(crate) fn decode(path: &Path) -> (u32, u32, Vec<Vec3>) {
    let image = image::open(path).unwrap().into_rgb16();
    let texels = image
        .pixels()
        .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) / 65535.0 * 2.0 - Vec3::ONE)
        .map(|v| v.normalize())
        .collect();
    (image.width(), image.height(), texels)
}

fn degrees(a: Vec3, b: Vec3) -> f64 {
    (a.as_dvec3().dot(b.as_dvec3()) / (a.length() as f64 * b.length() as f64))
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// The value below which `fraction` of `values` lie.
fn percentile(values: &mut [f64], fraction: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    values[((values.len() - 1) as f64 * fraction).round() as usize]
}

// Fails if a model baked onto itself is not (128, 128, 255) within one level on every texel
// (covered, margin and background), in each frame: the solve against LOW's own frame, the ray
// from the cage back to LOW's surface, or the encoding is wrong.
#[test]
fn a_model_baked_onto_itself_is_flat() {
    let dir = scratch("self");
    let low = sphere(&dir, "low.obj", 32, 16, &round, false);
    let low = low.to_str().unwrap();
    for frame in [
        &["--tangents", "mikktspace"][..],
        &["--tangents", "tutorial"],
        &["--tangents", "tutorial", "--normalize-tbn"],
    ] {
        let out = dir.join("self.png");
        let output = bake_cli(
            &[
                &[low, low, "-o", out.to_str().unwrap(), "--size", "128"][..],
                frame,
            ]
            .concat(),
        );
        assert!(output.status.success(), "{}", text(&output.stderr));
        let image = image::open(&out).unwrap().into_rgb8();
        let worst = image
            .pixels()
            .map(|p| {
                (p[0] as i32 - 128)
                    .abs()
                    .max((p[1] as i32 - 128).abs())
                    .max((p[2] as i32 - 255).abs())
            })
            .max()
            .unwrap();
        assert!(worst <= 1, "{frame:?}: a texel {worst} levels from flat");
        let said = text(&output.stdout);
        assert!(said.contains("every ray met HIGH"), "{said}");
    }
}

/// Where each texel centre of a `size²` map falls on LOW: (triangle, barycentrics), found by the
/// test's own walk over every triangle's UVs, in f64.
fn texel_owners(uvs: &[Vec2], size: u32) -> Vec<Vec<(usize, [f64; 3])>> {
    let n = size as usize;
    let mut owners = vec![Vec::new(); n * n];
    for (t, uv) in uvs.chunks_exact(3).enumerate() {
        let p: Vec<glam::DVec2> = uv
            .iter()
            .map(|c| glam::DVec2::new(c.x as f64, 1.0 - c.y as f64) * size as f64)
            .collect();
        let area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
        if area == 0.0 {
            continue;
        }
        let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
        for y in (lo.y.floor().max(0.0) as usize)..(hi.y.ceil() as usize).min(n) {
            for x in (lo.x.floor().max(0.0) as usize)..(hi.x.ceil() as usize).min(n) {
                let c = glam::DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let w = [
                    (p[2] - p[1]).perp_dot(c - p[1]) / area,
                    (p[0] - p[2]).perp_dot(c - p[2]) / area,
                    (p[1] - p[0]).perp_dot(c - p[0]) / area,
                ];
                if w.iter().all(|&w| w >= -1e-9) {
                    owners[y * n + x].push((t, w));
                }
            }
        }
    }
    owners
}

/// The bumps HIGH has in these tests: up to ±0.02, normals tilted up to about 7°.
fn relief() -> impl Fn(DVec3) -> (f64, DVec3) {
    bumps(0.02, 6.0)
}

/// The exact normal that a ray from LOW's cage meets on `relief`'s surface: LOW's point and
/// interpolated normal at `w` on triangle `t` (file coordinates), the cage `extrusion` out, back
/// along the normal; the surface found by marching and bisection on |p| − r(p/|p|).
fn exact_hit(low: &Low, t: usize, w: [f64; 3], extrusion: f64, relief: &Relief) -> DVec3 {
    let mix = |v: &[DVec3]| (0..3).map(|i| v[3 * t + i] * w[i]).sum::<DVec3>();
    let n = mix(&low.normals).normalize();
    let origin = mix(&low.points) + n * extrusion;
    let outside = |s: f64| {
        let p = origin - n * s;
        p.length() > relief(p.normalize()).0
    };
    let step = extrusion / 100.0;
    let mut inside = step;
    while outside(inside) {
        assert!(inside < 4.0 * extrusion, "the ray meets nothing");
        inside += step;
    }
    let mut out = inside - step;
    for _ in 0..60 {
        let middle = 0.5 * (out + inside);
        if outside(middle) {
            out = middle;
        } else {
            inside = middle;
        }
    }
    relief_point(relief, (origin - n * out).normalize()).1
}

/// What a MikkTSpace renderer draws from tangent-space texel `t` at `w` on triangle `tri`: the
/// interpolated T and N, B = sign · N × T, n = normalize(t.x T + t.y B + t.z N).
fn mikktspace_render(
    tangents: &[[f32; 4]],
    normals: &[DVec3],
    tri: usize,
    w: [f64; 3],
    t: Vec3,
) -> DVec3 {
    let mix = |f: &dyn Fn(usize) -> DVec3| (0..3).map(|i| f(3 * tri + i) * w[i]).sum::<DVec3>();
    let tangent = mix(&|k| Vec3::from_slice(&tangents[k][..3]).as_dvec3());
    let normal = mix(&|k| normals[k]);
    let sign: f64 = (0..3).map(|i| tangents[3 * tri + i][3] as f64 * w[i]).sum();
    let bitangent = normal.cross(tangent) * sign.signum();
    (tangent * t.x as f64 + bitangent * t.y as f64 + normal * t.z as f64).normalize()
}

/// LOW as the bake reads it, in its file's coordinates: corners, normals, UVs, MikkTSpace.
struct Low {
    points: Vec<DVec3>,
    normals: Vec<DVec3>,
    uvs: Vec<Vec2>,
    tangents: Vec<[f32; 4]>,
}

fn read_low(path: &Path) -> Low {
    let model = load_model(path, &MapOverrides::default()).unwrap();
    Low {
        points: model
            .soup
            .vertices
            .iter()
            .map(|&p| model.placement.to_file(p).as_dvec3())
            .collect(),
        normals: model.soup.normals.iter().map(|n| n.as_dvec3()).collect(),
        uvs: model.soup.uvs.clone(),
        tangents: tutorial13::tangent_source::mikktspace_tangents(&model.soup).unwrap(),
    }
}

// Fails if the baked normals, drawn by MikkTSpace's rule, are not the unit sphere's exact normals
// within 0.5° on 99 % of the texels whose centre lies on LOW (16-bit PNG): a wrong cage or ray
// direction, a wrong hit, HIGH's normals not interpolated, the frame not inverted, V upside down
// or the green channel flipped would each put most texels degrees off.
#[test]
fn a_fine_sphere_baked_onto_a_uv_sphere_gives_its_exact_normals() {
    let dir = scratch("sphere");
    let high = sphere(&dir, "high.obj", HIGH.0, HIGH.1, &relief(), false);
    let low_path = sphere(&dir, "low.obj", 32, 16, &round, false);
    let out = dir.join("baked.png");
    let output = bake_cli(&[
        high.to_str().unwrap(),
        low_path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "256",
        "--depth",
        "16",
        "--extrusion",
        "0.05",
    ]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let (size, _, texels) = decode(&out);
    let low = read_low(&low_path);
    let owners = texel_owners(&low.uvs, size);
    let (mut errors, mut flat_errors) = (Vec::new(), Vec::new());
    for (i, owners) in owners.iter().enumerate() {
        let Some(&(t, w)) = owners.first() else {
            continue;
        };
        let exact = exact_hit(&low, t, w, 0.05, &relief());
        let drawn = mikktspace_render(&low.tangents, &low.normals, t, w, texels[i]);
        errors.push(exact.angle_between(drawn).to_degrees());
        flat_errors.push(
            exact
                .angle_between(mikktspace_render(
                    &low.tangents,
                    &low.normals,
                    t,
                    w,
                    Vec3::Z,
                ))
                .to_degrees(),
        );
    }
    let covered = errors.len();
    let p99 = percentile(&mut errors, 0.99);
    let mean = errors.iter().sum::<f64>() / covered as f64;
    // The relief is there to be found: a flat map would be this far off.
    let flat_mean = flat_errors.iter().sum::<f64>() / covered as f64;
    eprintln!(
        "sphere bake: {covered} texels, mean {mean:.3}°, 99th percentile {p99:.3}° (a flat map: mean {flat_mean:.2}°)"
    );
    assert!(covered > 40_000, "{covered} texels covered");
    assert!(flat_mean > 2.0, "a flat map is only {flat_mean:.2}° off");
    assert!(p99 < 0.5, "99th percentile {p99:.3}° (mean {mean:.3}°)");
}

/// The library's bake of `high` onto `low` with `settings` (no file written).
fn bake_lib(high: &Path, low: &Path, settings: &BakeSettings) -> BakedMap {
    let files = BakeFiles::load(high, low, settings).unwrap();
    files.bake(settings).unwrap()
}

/// The bumpy HIGH baked onto a 32 × 16 UV sphere (its U mirrored with `mirror`) at 128², extrusion
/// 0.05 and maximum distance 0.1, in `space`; and LOW as the bake reads it.
fn bake_spheres(dir: PathBuf, mirror: bool, space: Space) -> (BakedMap, Low) {
    let high = sphere(&dir, "high.obj", HIGH.0, HIGH.1, &relief(), false);
    let low = sphere(&dir, "low.obj", 32, 16, &round, mirror);
    let settings = BakeSettings {
        width: 128,
        height: 128,
        extrusion: 0.05,
        max_distance: 0.1,
        space,
        ..BakeSettings::default()
    };
    (bake_lib(&high, &low, &settings), read_low(&low))
}

// Fails if an object-space bake is not the sphere's exact normals within 0.5° on 99 % of covered
// texels (the ray and hit without any tangent frame).
#[test]
fn an_object_space_bake_holds_the_exact_normals() {
    let (map, low) = bake_spheres(scratch("object"), false, Space::Object);
    let owners = texel_owners(&low.uvs, 128);
    let mut errors: Vec<f64> = owners
        .iter()
        .enumerate()
        .filter_map(|(i, o)| o.first().map(|&(t, w)| (i, t, w)))
        .map(|(i, t, w)| {
            exact_hit(&low, t, w, 0.05, &relief())
                .angle_between(map.normals[i].as_dvec3())
                .to_degrees()
        })
        .collect();
    let p99 = percentile(&mut errors, 0.99);
    assert!(p99 < 0.5, "99th percentile {p99:.3}°");
}

// Fails if mirrored UVs (both halves of the sphere on the same texels) leave one half wrong: each
// texel must give the exact normal through MikkTSpace's rule on both triangles that claim it, so
// nothing differs across the mirror's seam. Also fails if the overlap is not reported.
#[test]
fn mirrored_uvs_bake_right_on_both_halves() {
    let (map, low) = bake_spheres(scratch("mirrored"), true, Space::Tangent);
    assert!(
        map.stats.overlapping > map.stats.covered / 2,
        "{:?}",
        map.stats
    );
    let owners = texel_owners(&low.uvs, 128);
    let mut errors = [Vec::new(), Vec::new()];
    for (i, owners) in owners.iter().enumerate() {
        for &(t, w) in owners {
            let exact = exact_hit(&low, t, w, 0.05, &relief());
            let drawn = mikktspace_render(&low.tangents, &low.normals, t, w, map.normals[i]);
            // The half the triangle is on: x ≥ 0 is φ in 0..π.
            let half = usize::from(low.points[3 * t..3 * t + 3].iter().sum::<DVec3>().x < 0.0);
            errors[half].push(exact.angle_between(drawn).to_degrees());
        }
    }
    for (half, errors) in errors.iter_mut().enumerate() {
        assert!(errors.len() > 5000, "half {half}: {} samples", errors.len());
        let p99 = percentile(errors, 0.99);
        assert!(p99 < 0.5, "half {half}: 99th percentile {p99:.3}°");
    }
}

// Fails if the margin fills other texels than those within M (8-neighbour rings) of the covered
// ones, or the count it reports is not the texels it filled.
#[test]
fn the_margin_fills_m_texels_around_the_islands() {
    let dir = scratch("margin");
    let high = sphere(&dir, "high.obj", 64, 32, &round, false);
    // A quarter of the sphere's UVs: a small island in the corner, far from the map's edges.
    let low_path = dir.join("low.obj");
    let quarter = sphere_obj_text(32, 16, &round, false)
        .lines()
        .map(|line| match line.strip_prefix("vt ") {
            Some(uv) => {
                let mut c = uv.split(' ').map(|c| c.parse::<f32>().unwrap());
                let (u, v) = (c.next().unwrap(), c.next().unwrap());
                format!("vt {} {}", 0.25 + 0.5 * u, 0.25 + 0.5 * v)
            }
            None => line.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(&low_path, quarter).unwrap();
    let (w, h, m) = (96usize, 64usize, 5usize);
    let settings = BakeSettings {
        width: w as u32,
        height: h as u32,
        margin: m as u32,
        extrusion: 0.05,
        max_distance: 0.1,
        ..BakeSettings::default()
    };
    let map = bake_lib(&high, &low_path, &settings);
    let covered: Vec<(isize, isize)> = (0..w * h)
        .filter(|&i| map.states[i] == TexelState::Covered)
        .map(|i| ((i % w) as isize, (i / w) as isize))
        .collect();
    let mut filled = 0;
    for i in 0..w * h {
        let (x, y) = ((i % w) as isize, (i / w) as isize);
        let distance = covered
            .iter()
            .map(|&(cx, cy)| (cx - x).abs().max((cy - y).abs()))
            .min()
            .unwrap();
        let expected = match distance {
            0 => TexelState::Covered,
            d if d <= m as isize => TexelState::Margin,
            _ => TexelState::Empty,
        };
        assert_eq!(map.states[i], expected, "texel ({x}, {y}) at {distance}");
        filled += usize::from(expected == TexelState::Margin);
        if expected == TexelState::Empty {
            assert_eq!(map.normals[i], Vec3::Z, "background is flat");
        }
    }
    assert_eq!(map.stats.margin, filled);
}

// Fails if rays that meet nothing are not counted, the line is not a warning when they are all of
// them, or the advice names the wrong setting or a value that does not reach HIGH: LOW inside HIGH by more than the cage (every ray
// misses, HIGH is outside), then HIGH deeper inside than --max-distance (every ray misses, HIGH
// lies farther in).
#[test]
fn missed_rays_are_counted_with_what_to_change() {
    let dir = scratch("misses");
    let big = sphere(&dir, "big.obj", 64, 32, &round, false);
    let half: &Relief = &|_| (0.5, DVec3::ZERO);
    let small = sphere(&dir, "small.obj", 32, 16, half, false);
    let out = dir.join("m.png");
    // The setting that reaches HIGH: LOW (radius 0.5) 0.4 under the cage out to 0.6 inside HIGH
    // (radius 1), an extrusion of 0.5; HIGH 0.6 in from LOW's (radius 1) cage at 1.1. Both within
    // the spheres' facets (a few thousandths).
    let cases = [
        (&big, &small, "raise --extrusion to ", 0.5),
        (&small, &big, "raise --max-distance to ", 0.6),
    ];
    for (high, low, advice, enough) in cases {
        let output = bake_cli(&[
            high.to_str().unwrap(),
            low.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64",
            "--extrusion",
            "0.1",
        ]);
        assert!(output.status.success(), "{}", text(&output.stderr));
        let said = text(&output.stdout);
        let rays: usize = said
            .split(" with ")
            .nth(1)
            .unwrap()
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!(
            said.contains(&format!("\nwarning: {rays} rays (100.00 %) met nothing")),
            "{said}"
        );
        assert!(said.contains(&format!("for {rays} HIGH lies")), "{said}");
        let to: f64 = said
            .split(advice)
            .nth(1)
            .and_then(|rest| rest.split(' ').next())
            .and_then(|number| number.parse().ok())
            .unwrap_or_else(|| panic!("no '{advice}N': {said}"));
        assert!((to - enough).abs() < 0.01, "{to} against {enough}: {said}");
    }
}

// Fails if a distance beyond LOW's bounding radius (1: a unit UV sphere) is taken without a
// warning line that names it, the radius and the default (5 % of it), or if a bake at the default
// distances says any warning (every ray meets HIGH, nothing is out of scale).
#[test]
fn a_distance_beyond_the_model_is_said() {
    let dir = scratch("out-of-scale");
    let high = sphere(&dir, "high.obj", 64, 32, &bumps(0.02, 5.0), false);
    let low = sphere(&dir, "low.obj", 32, 16, &round, false);
    let out = dir.join("s.png");
    let said = |flags: &[&str]| {
        let mut args = vec![
            high.to_str().unwrap(),
            low.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "32",
        ];
        args.extend(flags);
        let output = bake_cli(&args);
        assert!(output.status.success(), "{}", text(&output.stderr));
        text(&output.stdout)
    };
    let quiet = said(&[]);
    assert!(quiet.contains("every ray met HIGH"), "{quiet}");
    assert!(!quiet.contains("warning"), "{quiet}");
    let far = said(&["--extrusion", "100"]);
    assert!(
        far.contains(
            "\nwarning: --extrusion 100 is beyond LOW's bounding radius 1: the rays start outside"
        ),
        "{far}"
    );
    assert!(far.contains("(the default, 5 %, is 0.05)"), "{far}");
    let long = said(&["--max-distance", "3"]);
    assert!(
        long.contains("\nwarning: --max-distance 3 is beyond LOW's bounding radius 1: a ray"),
        "{long}"
    );
    assert!(
        long.contains("twice the extrusion (the default, 0.1)"),
        "{long}"
    );
}

// Fails if the tutorial's summed frame is not said to be one no map can be right for (its T and B
// are tens of times N's length on a sphere placed on the tutorial's cylinder), or if MikkTSpace's
// is (it has right angles and unit vectors).
#[test]
fn the_tutorial_frame_is_said_to_skew_the_light() {
    let dir = scratch("skew");
    let low = sphere(&dir, "low.obj", 32, 16, &round, false);
    let low = low.to_str().unwrap();
    let out = dir.join("s.png");
    let said = |frame: &[&str]| {
        let output = bake_cli(
            &[
                &[low, low, "-o", out.to_str().unwrap(), "--size", "64"][..],
                frame,
            ]
            .concat(),
        );
        assert!(output.status.success(), "{}", text(&output.stderr));
        text(&output.stdout)
    };
    let tutorial = said(&["--tangents", "tutorial"]);
    assert!(
        tutorial.contains("no map can be right for this frame at 100.0 %"),
        "{tutorial}"
    );
    assert!(!said(&["--tangents", "mikktspace"]).contains("no map can be right"));
    // Normalized, the frame is nearly orthonormal: the line either goes or covers fewer texels.
    let normalized = said(&["--tangents", "tutorial", "--normalize-tbn"]);
    assert!(!normalized.contains("at 100.0 %"), "{normalized}");
}

// Fails if bad input panics, exits 0, says more or less than one line naming the file and reason,
// or writes anything.
#[test]
fn bad_input_is_one_line_and_nothing_written() {
    let dir = scratch("bad");
    let low = sphere(&dir, "low.obj", 8, 4, &round, false);
    let low = low.to_str().unwrap();
    let no_faces = dir.join("points.obj");
    std::fs::write(&no_faces, "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    let no_uvs = dir.join("no_uvs.obj");
    std::fs::write(
        &no_uvs,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nf 1/1 2/1 3/1\n",
    )
    .unwrap();
    let picture = dir.join("picture.obj");
    std::fs::write(&picture, b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR").unwrap();
    let out = dir.join("out").join("map.png");
    std::fs::create_dir_all(out.parent().unwrap()).unwrap();
    let out = out.to_str().unwrap();
    let missing_folder = dir.join("nowhere").join("map.png");
    let (jpg, bmp) = (out.replace(".png", ".jpg"), out.replace(".png", ".bmp"));
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![no_faces.to_str().unwrap(), low, "-o", out],
            "points.obj",
        ),
        (
            vec![low, no_uvs.to_str().unwrap(), "-o", out],
            "no_uvs.obj: no texel",
        ),
        (
            vec![picture.to_str().unwrap(), low, "-o", out],
            "picture.obj",
        ),
        (vec![low, "missing.obj", "-o", out], "missing.obj"),
        (
            vec![low, low, "-o", missing_folder.to_str().unwrap()],
            "nowhere",
        ),
        (vec![low, low, "-o", &jpg], "name the output .bmp or .png"),
        (vec![low, low, "-o", &bmp, "--depth", "16"], "PNG only"),
        (vec![low, low, "-o", out, "--size", "0"], "1 to 16384"),
        (vec![low, low, "-o", out, "--size", "16385x8"], "1 to 16384"),
        (
            vec![low, low, "-o", out, "--extrusion", "-1"],
            "--extrusion",
        ),
        (
            vec![low, low, "-o", out, "--normalize-tbn"],
            "--normalize-tbn",
        ),
    ];
    for (args, reason) in cases {
        assert_refused(&args, reason, &dir.join("out"));
    }
}

/// `tutorial13 bake ARGS` fails without a panic, in one line holding `reason`, and writes nothing
/// under `out`.
pub(crate) fn assert_refused(args: &[&str], reason: &str, out: &Path) {
    let output = bake_cli(args);
    let err = text(&output.stderr);
    assert!(!output.status.success(), "{args:?} succeeded");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert!(err.contains(reason), "{args:?}: {err}");
    let error_lines = err
        .lines()
        .filter(|l| l.contains("error") || l.starts_with("tutorial13:"))
        .count();
    assert_eq!(error_lines, 1, "{args:?}: {err}");
    assert!(
        crate::common::files_under(out).is_empty(),
        "{args:?} wrote a file"
    );
}

// Fails if --tangents tutorial and mikktspace give the same map (the frames differ on a sphere:
// T's length and direction), which would mean the option is not reaching the bake.
#[test]
fn the_frame_option_reaches_the_bake() {
    let dir = scratch("frames");
    let high = sphere(&dir, "high.obj", 128, 64, &relief(), false);
    let low = sphere(&dir, "low.obj", 16, 8, &round, false);
    let bake = |tangents| {
        let settings = BakeSettings {
            width: 64,
            height: 64,
            extrusion: 0.05,
            max_distance: 0.1,
            tangents,
            ..BakeSettings::default()
        };
        bake_lib(&high, &low, &settings)
    };
    let (mikk, tutorial) = (
        bake(TangentSource::MikkTSpace),
        bake(TangentSource::Tutorial),
    );
    let tilt = |m: &BakedMap| {
        m.normals
            .iter()
            .map(|n| degrees(*n, Vec3::Z))
            .fold(0.0, f64::max)
    };
    eprintln!(
        "largest tilt: mikk {:.4}° tutorial {:.4}° stats {:?}",
        tilt(&mikk),
        tilt(&tutorial),
        mikk.stats
    );
    let largest = mikk
        .normals
        .iter()
        .zip(&tutorial.normals)
        .map(|(a, b)| degrees(*a, *b))
        .fold(0.0, f64::max);
    assert!(
        largest > 1.0,
        "the two frames' maps differ by at most {largest:.3}°"
    );
}

// Fails if `bake --tangents derivative` (the scenes' per-pixel frame, which has no corner frames
// to bake for) panics, exits 0, writes the map, or is not one line naming the flag and why; if the
// library's `BakeFiles::load` takes it or reads the files first (they do not exist: the error would
// name them); or if `bake --help` lists `derivative` among the frames, or loses one of the three it
// bakes, their help, or its own default (mikktspace, where the scenes' is the tutorial's). Each of
// the three bakes in `a_model_baked_onto_itself_is_flat` (mikktspace, tutorial) and
// `a_gltf_lows_own_tangents_are_baked_in` (file).
#[test]
fn the_bake_refuses_the_per_pixel_frame() {
    let dir = scratch("derivative");
    let low = sphere(&dir, "low.obj", 8, 4, &round, false);
    let low = low.to_str().unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let map = out.join("map.png");
    assert_refused(
        &[
            low,
            low,
            "-o",
            map.to_str().unwrap(),
            "--tangents",
            "derivative",
        ],
        "invalid value 'derivative' for '--tangents <TANGENTS>': the per-pixel frame is solved \
         from screen-space derivatives",
        &out,
    );
    let settings = BakeSettings {
        tangents: TangentSource::Derivative,
        ..BakeSettings::default()
    };
    let missing = dir.join("missing.obj");
    let refused = BakeFiles::load(&missing, &missing, &settings)
        .err()
        .map(|e| e.to_string());
    let refused = refused.expect("the library bakes for the per-pixel frame");
    assert!(
        refused.starts_with("--tangents derivative: the per-pixel frame")
            && !refused.contains('\n'),
        "{refused}"
    );
    let help = text(&bake_cli(&["--help"]).stdout);
    let start = help
        .find("--tangents <TANGENTS>")
        .expect("--tangents in bake --help");
    let end = start + help[start..].find("--normalize-tbn").unwrap();
    let listed = &help[start..end];
    for frame in [
        "- mikktspace: MikkTSpace, computed from LOW",
        "- file:",
        "- tutorial:   The tutorial's computeTangentBasis",
        "[default: mikktspace]",
    ] {
        assert!(listed.contains(frame), "{frame} not in {listed}");
    }
    assert!(!listed.contains("derivative"), "{listed}");
}

// Fails if a learner's model drawn with the tutorial's summed frame (26× stretched on this sphere)
// is not warned of once with the keys that change it, if MikkTSpace's frame or the normalized TBN
// are warned of, or if the information lines (no material, no map_Ks) are warnings.
#[test]
fn a_model_drawn_with_a_frame_far_from_mikktspace_is_warned_of_once() {
    let dir = scratch("far-frame");
    sphere(&dir, "low.obj", 32, 16, &round, false);
    let warnings = |args: &[&str]| {
        let output = run(tutorial13()
            .args(["--headless", "--screenshot", "x.png", "--model", "low.obj"])
            .args(args)
            .current_dir(&dir));
        assert!(output.status.success(), "{}", text(&output.stderr));
        text(&output.stderr)
            .lines()
            .filter(|l| l.starts_with("[WARN"))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    let tutorial = warnings(&[]);
    assert_eq!(tutorial.len(), 1, "{tutorial:?}");
    assert!(
        tutorial[0].contains("stretched 26.4×") && tutorial[0].contains("F steps to MikkTSpace"),
        "{tutorial:?}"
    );
    assert_eq!(
        warnings(&["--tangents", "mikktspace"]),
        Vec::<String>::new()
    );
    assert_eq!(warnings(&["--normalize-tbn"]), Vec::<String>::new());
}

/// The drawn-back pair's relief: r = 1 − a (1 − cos(k x) cos(k z)), dents up to 2a deep that
/// leave the poles (and a lattice of points) at radius 1, normals tilted up to about 20°.
fn drawn_relief() -> impl Fn(DVec3) -> (f64, DVec3) {
    let (a, k) = (0.04, 8.0);
    move |u: DVec3| {
        let (cx, sx, cz, sz) = (
            (k * u.x).cos(),
            (k * u.x).sin(),
            (k * u.z).cos(),
            (k * u.z).sin(),
        );
        (
            1.0 - a * (1.0 - cx * cz),
            DVec3::new(-a * k * sx * cz, 0.0, -a * k * cx * sz),
        )
    }
}

/// Pixels inside both frames' silhouettes (no background within 2 pixels in either).
fn inside_both(a: &image::RgbImage, b: &image::RgbImage) -> Vec<(u32, u32)> {
    let (w, h) = a.dimensions();
    let background = |x: u32, y: u32| {
        crate::common::is_background(a.get_pixel(x, y))
            || crate::common::is_background(b.get_pixel(x, y))
    };
    (2..h - 2)
        .flat_map(|y| (2..w - 2).map(move |x| (x, y)))
        .filter(|&(x, y)| !(y - 2..=y + 2).any(|yy| (x - 2..=x + 2).any(|xx| background(xx, yy))))
        .collect()
}

/// Mean and 99th percentile of the per-pixel largest channel difference over `pixels`.
fn difference(a: &image::RgbImage, b: &image::RgbImage, pixels: &[(u32, u32)]) -> (f64, f64) {
    let mut d: Vec<f64> = pixels
        .iter()
        .map(|&(x, y)| {
            let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
            (0..3)
                .map(|c| (p[c] as i32 - q[c] as i32).abs())
                .max()
                .unwrap() as f64
        })
        .collect();
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    (mean, percentile(&mut d, 0.99))
}

// Fails if LOW drawn with its bake, in the frame it was baked for (MikkTSpace), is not HIGH drawn
// alone within 3 levels on average and 14 at the 99th percentile inside both silhouettes (within
// 0.8 of their radius, past which the rim shows parallax, which no normal map has), if LOW without the map is not at least 3
// times as far, or if the same map drawn in the tutorial's frame is not far off (at least 20
// levels on average): the bake and the renderer must agree on the frame, V, green and the inverse.
// Also makes docs/tangent-space-sync.png from the same frames (checked as the docs' other pictures).
#[test]
fn drawn_back_in_its_frame_a_bake_looks_like_high() {
    let dir = scratch("drawn");
    // Each model is placed on the tutorial's cylinder by its bounding sphere, and the light is
    // placed with it: HIGH's relief reaches radius 1 only at the poles, as LOW does, so that the
    // two are placed alike and lit from one place.
    sphere(&dir, "high.obj", HIGH.0, HIGH.1, &drawn_relief(), false);
    sphere(&dir, "low.obj", 32, 16, &round, false);
    image::RgbImage::from_pixel(4, 4, image::Rgb([40, 40, 40]))
        .save(dir.join("grey.png"))
        .unwrap();
    image::RgbImage::from_pixel(4, 4, image::Rgb([0, 0, 0]))
        .save(dir.join("black.png"))
        .unwrap();
    for (map, frame) in [
        ("mikk.png", &[][..]),
        ("tutorial.png", &["--tangents", "tutorial"]),
        (
            "normalized.png",
            &["--tangents", "tutorial", "--normalize-tbn"],
        ),
    ] {
        let output = run(tutorial13()
            .args([
                "bake",
                "high.obj",
                "low.obj",
                "-o",
                map,
                "--size",
                "1024",
                "--extrusion",
                "0.08",
            ])
            .args(frame)
            .current_dir(&dir));
        assert!(output.status.success(), "{}", text(&output.stderr));
    }
    // A far light (its falloff the same on HIGH's dents as on LOW's surface), grey and matte.
    let draw = |name: &str, args: &[&str]| {
        let materials = [
            "--diffuse",
            "grey.png",
            "--specular",
            "black.png",
            "--light",
            "40,25,20",
            "--light-power",
            "16000",
        ];
        crate::common::headless_screenshot(&dir, name, &[args, &materials].concat())
    };
    let high = draw(
        "high.png",
        &["--model", "high.obj", "--tangents", "mikktspace"],
    );
    let frames = [
        (
            "mikktspace",
            draw(
                "low-mikk.png",
                &[
                    "--model",
                    "low.obj",
                    "--normal-map",
                    "mikk.png",
                    "--tangents",
                    "mikktspace",
                ],
            ),
        ),
        (
            "mikktspace map, tutorial frame",
            draw(
                "low-mikk-tutorial.png",
                &["--model", "low.obj", "--normal-map", "mikk.png"],
            ),
        ),
        (
            "tutorial",
            draw(
                "low-tutorial.png",
                &["--model", "low.obj", "--normal-map", "tutorial.png"],
            ),
        ),
        (
            "tutorial normalized",
            draw(
                "low-normalized.png",
                &[
                    "--model",
                    "low.obj",
                    "--normal-map",
                    "normalized.png",
                    "--normalize-tbn",
                ],
            ),
        ),
        (
            "no map",
            draw(
                "low-flat.png",
                &["--model", "low.obj", "--tangents", "mikktspace"],
            ),
        ),
    ];
    // Inside both silhouettes, within 0.8 of the silhouette's radius: past it the surface turns
    // away and LOW's surface shows the relief where HIGH's rim stands in front of it (parallax,
    // which no normal map has).
    let inside = inside_both(&high, &frames[0].1);
    let radius = (inside.len() as f64 / std::f64::consts::PI).sqrt();
    let centre = inside
        .iter()
        .fold((0.0, 0.0), |c, &(x, y)| (c.0 + x as f64, c.1 + y as f64));
    let centre = (
        centre.0 / inside.len() as f64,
        centre.1 / inside.len() as f64,
    );
    let pixels: Vec<(u32, u32)> = inside
        .iter()
        .copied()
        .filter(|&(x, y)| (x as f64 - centre.0).hypot(y as f64 - centre.1) < 0.8 * radius)
        .collect();
    assert!(
        pixels.len() > 100_000,
        "{} pixels inside both",
        pixels.len()
    );
    let differences: Vec<(f64, f64)> = frames
        .iter()
        .map(|(_, f)| difference(&high, f, &pixels))
        .collect();
    for ((name, _), (mean, p99)) in frames.iter().zip(&differences) {
        eprintln!("drawn back, {name}: mean {mean:.2}, 99th percentile {p99:.0} levels from HIGH");
    }
    let (mean, p99) = differences[0];
    assert!(
        mean <= 3.0 && p99 <= 14.0,
        "in its own frame: mean {mean:.2}, 99th percentile {p99}"
    );
    let (flat, _) = differences[4];
    assert!(flat >= 3.0 * mean, "without the map: mean only {flat:.2}");
    let (mean, _) = differences[1];
    assert!(mean >= 20.0, "in the tutorial's frame: mean only {mean:.2}");
    // The picture: HIGH, then each of LOW's frames, 256 × 192 each.
    let tile = |image: &image::RgbImage| {
        image::imageops::resize(image, 256, 192, image::imageops::FilterType::Triangle)
    };
    let mut picture = image::RgbImage::new(768, 384);
    for (i, image) in std::iter::once(&high)
        .chain(frames.iter().map(|(_, f)| f))
        .enumerate()
    {
        let (x, y) = (256 * (i as i64 % 3), 192 * (i as i64 / 3));
        image::imageops::replace(&mut picture, &tile(image), x, y);
    }
    crate::common::check_docs_picture(&picture, "docs/tangent-space-sync.png", "bake");
}

// Fails if HIGH exported without a UV layout (a sculpt: `f v//vn` corners, no `vt`) is refused or
// baked differently from the same HIGH with UVs (HIGH's UVs take no part in a bake).
#[test]
fn high_without_uvs_bakes_the_same_map() {
    let dir = scratch("high-no-uvs");
    let high = sphere(&dir, "high.obj", 64, 32, &relief(), false);
    let low = sphere(&dir, "low.obj", 16, 8, &round, false);
    let sculpt = without_uvs(&std::fs::read_to_string(&high).unwrap());
    let sculpt_path = dir.join("sculpt.obj");
    std::fs::write(&sculpt_path, sculpt).unwrap();
    let mut maps = Vec::new();
    for (high, name) in [(&high, "with.png"), (&sculpt_path, "without.png")] {
        let out = dir.join(name);
        let output = bake_cli(&[
            high.to_str().unwrap(),
            low.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64",
        ]);
        assert!(output.status.success(), "{}", text(&output.stderr));
        maps.push(image::open(&out).unwrap().into_rgb8());
    }
    assert!(maps[0] == maps[1], "the maps differ");
}

/// An OBJ's triangles (`v`, `vt`, `vn` and `f v/vt/vn` lines, as [`sphere`] writes them) as a binary
/// glTF, corner by corner: the floats the OBJ holds, V turned to glTF's (down the picture), with
/// TEXCOORD_0 or without, and with `tangents` (one per corner) where given.
pub fn obj_as_glb(obj: &Path, uvs: bool, tangents: Option<&[[f32; 4]]>) -> Vec<u8> {
    let text = std::fs::read_to_string(obj).unwrap();
    let floats = |prefix: &str| -> Vec<Vec<f32>> {
        let lines = text.lines().filter_map(|l| l.strip_prefix(prefix));
        lines
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (v, vt, vn) = (floats("v "), floats("vt "), floats("vn "));
    let (mut positions, mut texcoords, mut normals) = (Vec::new(), Vec::new(), Vec::new());
    for face in text.lines().filter_map(|l| l.strip_prefix("f ")) {
        for corner in face.split_whitespace() {
            let i: Vec<usize> = corner.split('/').map(|i| i.parse().unwrap()).collect();
            positions.extend(&v[i[0] - 1]);
            texcoords.extend([vt[i[1] - 1][0], 1.0 - vt[i[1] - 1][1]]);
            normals.extend(&vn[i[2] - 1]);
        }
    }
    let mut buffers = crate::gltf::Buffers::default();
    let mut attributes = vec![
        format!(
            r#""POSITION":{}"#,
            buffers.floats(&positions, 3, "VEC3", true)
        ),
        format!(r#""NORMAL":{}"#, buffers.floats(&normals, 3, "VEC3", false)),
    ];
    if uvs {
        let accessor = buffers.floats(&texcoords, 2, "VEC2", false);
        attributes.push(format!(r#""TEXCOORD_0":{accessor}"#));
    }
    if let Some(tangents) = tangents {
        let flat: Vec<f32> = tangents.iter().flatten().copied().collect();
        let accessor = buffers.floats(&flat, 4, "VEC4", false);
        attributes.push(format!(r#""TANGENT":{accessor}"#));
    }
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{{}}}}}]}}],
"buffers":[{{"byteLength":{}}}],"bufferViews":[{}],"accessors":[{}]}}"#,
        attributes.join(","),
        buffers.bin.len(),
        buffers.views.join(","),
        buffers.accessors.join(",")
    );
    crate::gltf::glb(&json, &buffers.bin)
}

/// The largest difference of two 16-bit maps' components, in levels of 65535 (their texels are
/// decoded and normalized again: a stored level is within 0.5 of this).
fn largest_levels(a: &[Vec3], b: &[Vec3]) -> f32 {
    let largest = a.iter().zip(b).map(|(a, b)| (*a - *b).abs().max_element());
    largest.fold(0.0, f32::max) * 32767.5
}

/// `tutorial13 bake HIGH LOW -o NAME --size 64 ARGS…` in `dir`, the map as 16-bit texels.
fn bake_in(dir: &Path, high: &Path, low: &Path, name: &str, args: &[&str]) -> Vec<Vec3> {
    let out = dir.join(name);
    let mut all = vec![high.to_str().unwrap(), low.to_str().unwrap()];
    all.extend(["-o", out.to_str().unwrap(), "--size", "64"]);
    all.extend(args);
    let output = bake_cli(&all);
    assert!(output.status.success(), "{}", text(&output.stderr));
    decode(&out).2
}

// Fails if a glTF HIGH without TEXCOORD_0 (a sculpt exported without a UV layout) is refused or
// bakes differently from the same glTF with its UVs, or if a glTF HIGH bakes more than one level
// (of 65535) away from the OBJ it was written from: the glTF holds the OBJ's floats, and only its
// normals are normalized as they are read.
#[test]
fn a_gltf_high_without_uvs_bakes_the_same_map() {
    let dir = scratch("gltf-high");
    let high = sphere(&dir, "high.obj", 64, 32, &relief(), false);
    let low = sphere(&dir, "low.obj", 16, 8, &round, false);
    let mut maps = Vec::new();
    for (uvs, name) in [(true, "with.glb"), (false, "without.glb")] {
        let path = dir.join(name);
        std::fs::write(&path, obj_as_glb(&high, uvs, None)).unwrap();
        maps.push(bake_in(
            &dir,
            &path,
            &low,
            &format!("{name}.png"),
            &["--depth", "16"],
        ));
    }
    assert!(maps[0] == maps[1], "the maps differ");
    let obj = bake_in(&dir, &high, &low, "obj.png", &["--depth", "16"]);
    let levels = largest_levels(&obj, &maps[0]);
    assert!(
        levels <= 1.0,
        "the OBJ's and the glTF's maps differ by {levels} levels"
    );
}

// Fails if `--tangents file` does not bake in a glTF LOW's own TANGENTs: with MikkTSpace's
// tangents written into the file, the map must be `--tangents mikktspace`'s within one level of
// 65535 (the reader normalizes a file's tangents again, which moves their last bits); with
// each corner's tangent turned a quarter round its normal (T' = B, so B' = -T), every texel's
// (x, y) must become (y, -x), within a stated angle (the turned tangents are interpolated across a
// triangle, which a quarter turn of the interpolated frame is not, exactly).
#[test]
fn a_gltf_lows_own_tangents_are_baked_in() {
    let dir = scratch("file-tangents");
    let high = sphere(&dir, "high.obj", 128, 64, &relief(), false);
    let low_obj = sphere(&dir, "low.obj", 16, 8, &round, false);
    let bare = dir.join("bare.glb");
    std::fs::write(&bare, obj_as_glb(&low_obj, true, None)).unwrap();
    let soup = load_model(&bare, &MapOverrides::default()).unwrap().soup;
    let mikk = tutorial13::tangent_source::mikktspace_tangents(&soup).unwrap();
    let turned: Vec<[f32; 4]> = mikk
        .iter()
        .zip(&soup.normals)
        .map(|(t, n)| {
            let b = t[3] * n.cross(Vec3::from_slice(t));
            [b.x, b.y, b.z, t[3]]
        })
        .collect();
    let args = ["--depth", "16", "--tangents"];
    let computed = bake_in(
        &dir,
        &high,
        &bare,
        "computed.png",
        &[&args[..], &["mikktspace"]].concat(),
    );
    let mut maps = Vec::new();
    for (tangents, name) in [(&mikk, "mikk.glb"), (&turned, "turned.glb")] {
        let low = dir.join(name);
        std::fs::write(&low, obj_as_glb(&low_obj, true, Some(tangents))).unwrap();
        maps.push(bake_in(
            &dir,
            &high,
            &low,
            &format!("{name}.png"),
            &[&args[..], &["file"]].concat(),
        ));
    }
    let levels = largest_levels(&computed, &maps[0]);
    assert!(
        levels <= 1.0,
        "the file's MikkTSpace tangents bake {levels} levels away"
    );
    let mut angles: Vec<f64> = computed
        .iter()
        .zip(&maps[1])
        .filter(|(c, _)| (**c - Vec3::Z).length() > 1e-3)
        .map(|(c, t)| degrees(Vec3::new(c.y, -c.x, c.z), *t))
        .collect();
    let tilted = angles.len();
    let p99 = percentile(&mut angles, 0.99);
    let largest = angles[tilted - 1];
    eprintln!("turned tangents: {tilted} tilted texels, p99 {p99:.4}°, largest {largest:.4}°");
    assert!(
        tilted > 500,
        "only {tilted} texels are tilted: the test sees nothing"
    );
    assert!(
        p99 < 0.5,
        "(x, y) → (y, -x) within {p99:.3}° at the 99th percentile"
    );
}
