//! OBJ text made by code: the tutorial's cylinder in its file's layout, which `make_assets` writes
//! as `assets/cylinder.obj` ([`tutorial_cylinder_obj_text`]), and the meshes the tests, benchmarks
//! and fuzz seeds generate: open cylinders of any size ([`grid_cylinder_obj_text`]), cut into UV
//! charts ([`charted_cylinder_obj_text`]), and UV spheres with a relief ([`sphere_obj_text`]).

/// The tutorial's U: 2.2407 on the first column, falling by 3.7134 / 32 per segment (so the texture
/// reads left to right seen from outside) and ending on a seam duplicate at 2.3567.
const U_START: f64 = 2.2407;
const U_TURNS: f64 = 3.7134;

/// The tutorial's cylinder as OBJ text, in its file's layout (see [`grid_cylinder_obj_text`]
/// for cylinders of any size): radius 1, y from 0 to 2, `segments` (at least 3) quads
/// around, no caps.
///
/// Laid out like the tutorial's file: the bottom ring then the top ring of positions (ring point `i`
/// at angle `2πi/segments` from -Z towards +X), one radial normal per column, two UVs per column plus
/// a seam column (so `2 * (segments + 1)` UVs), and two triangles per quad wound counter-clockwise
/// seen from outside.
pub fn tutorial_cylinder_obj_text(segments: u32) -> String {
    use std::fmt::Write as _;

    let n = segments.max(3);
    let mut text = String::new();
    let _ = writeln!(
        text,
        "# tutorial13: cylinder, radius 1, height 2, {n} segments"
    );
    let ring: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let angle = std::f64::consts::TAU * f64::from(i) / f64::from(n);
            (angle.sin(), -angle.cos())
        })
        .collect();
    for y in [0.0, 2.0] {
        for &(x, z) in &ring {
            let _ = writeln!(text, "v {} {} {}", fixed(x), fixed(y), fixed(z));
        }
    }
    // Column i's U; the last column repeats ring point n-1 one turn further, so that the seam quad
    // (n-1 → 0) continues the U ramp instead of running backwards across the whole texture.
    let du = U_TURNS / f64::from(n);
    let column_u = |i: u32| U_START - f64::from(i) * du;
    for u in (0..n).map(column_u).chain([column_u(n - 1) + U_TURNS]) {
        let _ = writeln!(text, "vt {} {}", fixed(u), fixed(0.0));
        let _ = writeln!(text, "vt {} {}", fixed(u), fixed(1.0));
    }
    for &(x, z) in &ring {
        let _ = writeln!(text, "vn {} {} {}", fixed(x), fixed(0.0), fixed(z));
    }
    let _ = writeln!(text, "s 1");
    for i in 0..n {
        // 1-based OBJ indices of this quad's corners: bottom/top at columns i and i+1 (wrapping).
        let j = (i + 1) % n;
        let (b0, t0, b1, t1) = (i + 1, n + i + 1, j + 1, n + j + 1);
        // UV columns: i's pair, and the next pair; the seam quad uses the duplicate pair for i.
        let (uv_col0, uv_col1) = if j == 0 { (n, 0) } else { (i, j) };
        let (uv_b0, uv_t0) = (2 * uv_col0 + 1, 2 * uv_col0 + 2);
        let (uv_b1, uv_t1) = (2 * uv_col1 + 1, 2 * uv_col1 + 2);
        let (n0, n1) = (i + 1, j + 1);
        // Ring angle grows towards +X from -Z, i.e. clockwise seen from above; going up then along
        // the ring is counter-clockwise seen from outside.
        let _ = writeln!(
            text,
            "f {b0}/{uv_b0}/{n0} {t0}/{uv_t0}/{n0} {t1}/{uv_t1}/{n1}"
        );
        let _ = writeln!(
            text,
            "f {b0}/{uv_b0}/{n0} {t1}/{uv_t1}/{n1} {b1}/{uv_b1}/{n1}"
        );
    }
    text
}

/// Six decimals, never `-0.000000`.
fn fixed(x: f64) -> String {
    let s = format!("{x:.6}");
    match s.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => s,
    }
}

/// OBJ text of an open cylinder around the y axis (sides only, smooth radial normals) of any size:
/// `segments` around, `rings` bands from y = 0 to y = `height`, U wrapping the texture `u_repeat`
/// times around (growing to the right seen from outside) and V running 0..1 upwards. Faces are
/// counter-clockwise seen from outside. The seam repeats its positions' UVs at U = `u_repeat`, as the
/// tutorial's file does, so indexing keeps two vertices there.
///
/// Used for the benchmarks' large meshes and for tests that need rings or odd UV scales; the project's
/// `assets/cylinder.obj` comes from [`tutorial_cylinder_obj_text`], which follows the
/// tutorial's file layout line for line (one band, its U offsets).
pub fn grid_cylinder_obj_text(
    segments: u32,
    rings: u32,
    radius: f32,
    height: f32,
    u_repeat: f32,
) -> String {
    use std::fmt::Write;
    let mut text = String::with_capacity((segments as usize + 1) * (rings as usize + 1) * 96);
    let _ = writeln!(
        text,
        "# tutorial13: open cylinder, {segments} segments, {rings} rings, radius {radius}, height {height}"
    );
    write_positions(&mut text, segments, rings, radius, height);
    for ring in 0..=rings {
        let v = ring as f32 / rings as f32;
        for s in 0..=segments {
            // U decreases with the angle, as in the tutorial's file: seen from outside, U grows to
            // the right and the texture is not mirrored.
            let u = u_repeat * (segments - s) as f32 / segments as f32;
            let _ = writeln!(text, "vt {u:.6} {v:.6}");
        }
    }
    write_normals(&mut text, segments);
    // 1-based OBJ indices of the corner at (segment s, ring r); s may be `segments` (the seam's UV).
    let v = |s: u32, r: u32| r * segments + s % segments + 1;
    let vt = |s: u32, r: u32| r * (segments + 1) + s + 1;
    let vn = |s: u32| s % segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let corner = |s: u32, r: u32| format!("{}/{}/{}", v(s, r), vt(s, r), vn(s));
            write_quad(&mut text, corner, s, r);
        }
    }
    text
}

/// OBJ text of the same open cylinder as [`grid_cylinder_obj_text`], with its UVs laid out the way
/// modelling tools export them: the surface cut into charts of `chart × chart` quads, each chart with
/// its own island in a [0, 1]² atlas (half of its atlas cell, the rest padding). Positions on a chart
/// border are repeated with another UV for each chart they belong to (a seam), so they index to
/// several vertices; faces are written chart by chart. Each chart keeps its own vertices, so the mesh
/// indexes to `Σ (chart width + 1) × (chart height + 1)` vertices while positions stay more than 0.01
/// apart and the padding (half a cell: 0.5 / charts across, or up) is wider than 0.01.
pub fn charted_cylinder_obj_text(
    segments: u32,
    rings: u32,
    radius: f32,
    height: f32,
    chart: u32,
) -> String {
    use std::fmt::Write;
    let (across, up) = (segments.div_ceil(chart), rings.div_ceil(chart));
    let mut text = String::with_capacity((segments as usize + 1) * (rings as usize + 1) * 128);
    let _ = writeln!(
        text,
        "# tutorial13: open cylinder, {segments} segments, {rings} rings, radius {radius}, height {height}, charts of {chart}"
    );
    write_positions(&mut text, segments, rings, radius, height);
    write_normals(&mut text, segments);
    // Each chart: its UV island, then its faces (OBJ indices may point back at any earlier `vt`).
    let mut vt_count = 0;
    for (cr, cs) in (0..up).flat_map(|cr| (0..across).map(move |cs| (cr, cs))) {
        let (s0, r0) = (cs * chart, cr * chart);
        let (w, h) = (chart.min(segments - s0), chart.min(rings - r0));
        for r in 0..=h {
            for s in 0..=w {
                let u = (cs as f32 + 0.5 * s as f32 / chart as f32) / across as f32;
                let v = (cr as f32 + 0.5 * r as f32 / chart as f32) / up as f32;
                let _ = writeln!(text, "vt {u:.6} {v:.6}");
            }
        }
        let corner = |s: u32, r: u32| {
            let (gs, gr) = (s0 + s, r0 + r);
            let v = gr * segments + gs % segments + 1;
            let vt = vt_count + r * (w + 1) + s + 1;
            format!("{v}/{vt}/{}", gs % segments + 1)
        };
        for r in 0..h {
            for s in 0..w {
                write_quad(&mut text, corner, s, r);
            }
        }
        vt_count += (w + 1) * (h + 1);
    }
    text
}

/// The cylinder's `v` lines: `segments` around each of the `rings + 1` circles, bottom to top.
/// The two triangles of the grid cell at (segment `s`, ring `r`), `corner` giving each corner's
/// `v/vt/vn`. Angles grow from -z towards +x: seen from outside, (s, r) → (s, r+1) → (s+1, r+1) is
/// counter-clockwise.
fn write_quad(text: &mut String, corner: impl Fn(u32, u32) -> String, s: u32, r: u32) {
    use std::fmt::Write;
    let (a, b, c, d) = (
        corner(s, r),
        corner(s + 1, r),
        corner(s + 1, r + 1),
        corner(s, r + 1),
    );
    let _ = writeln!(text, "f {a} {d} {c}\nf {a} {c} {b}");
}

fn write_positions(text: &mut String, segments: u32, rings: u32, radius: f32, height: f32) {
    use std::fmt::Write;
    for ring in 0..=rings {
        let y = height * ring as f32 / rings as f32;
        for s in 0..segments {
            let (sin, cos) = angle(s, segments).sin_cos();
            let _ = writeln!(text, "v {:.6} {:.6} {:.6}", radius * sin, y, -radius * cos);
        }
    }
}

/// The cylinder's `vn` lines: one radial normal per segment.
fn write_normals(text: &mut String, segments: u32) {
    use std::fmt::Write;
    for s in 0..segments {
        let (sin, cos) = angle(s, segments).sin_cos();
        let _ = writeln!(text, "vn {:.6} 0.000000 {:.6}", sin, -cos);
    }
}

fn angle(s: u32, segments: u32) -> f32 {
    std::f32::consts::TAU * s as f32 / segments as f32
}

/// A sphere's relief for [`sphere_obj_text`]: the radius in unit direction u, and the gradient of
/// that radius as a function of u (for the exact normals).
pub type Relief = dyn Fn(glam::DVec3) -> (f64, glam::DVec3);

/// A round sphere of radius 1 as a [`Relief`].
pub fn round(_direction: glam::DVec3) -> (f64, glam::DVec3) {
    (1.0, glam::DVec3::ZERO)
}

/// Bumps: r = 1 + `amplitude` · cos(k x) cos(k y) cos(k z) of the unit direction (x, y, z); smooth
/// everywhere, the poles included, and the same under x → −x (a mirrored half sees the same relief).
pub fn bumps(amplitude: f64, k: f64) -> impl Fn(glam::DVec3) -> (f64, glam::DVec3) {
    move |u| {
        let (c, s) = (
            glam::DVec3::new((k * u.x).cos(), (k * u.y).cos(), (k * u.z).cos()),
            glam::DVec3::new((k * u.x).sin(), (k * u.y).sin(), (k * u.z).sin()),
        );
        let gradient =
            -amplitude * k * glam::DVec3::new(s.x * c.y * c.z, c.x * s.y * c.z, c.x * c.y * s.z);
        (1.0 + amplitude * c.x * c.y * c.z, gradient)
    }
}

/// The point of a sphere whose radius is `relief`'s in unit direction `u`, and its exact unit
/// normal: the gradient of |p| − r(p / |p|), u tilted against the radius's slope.
pub fn relief_point(relief: &Relief, u: glam::DVec3) -> (glam::DVec3, glam::DVec3) {
    let (r, gradient) = relief(u);
    // Only the gradient's part across u moves the normal (r does not change along u).
    let across = gradient - u * gradient.dot(u);
    (u * r, (u - across / r).normalize())
}

/// The unit direction at polar angle θ (from +y) and azimuth φ (from +z towards +x).
pub fn sphere_direction(theta: f64, phi: f64) -> glam::DVec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    glam::DVec3::new(st * sp, ct, st * cp)
}

/// OBJ text of a UV sphere laid out as Blender's "UV Sphere" exports it: `segments` around (U from
/// 0 to 1, its seam repeated), `rings` from the top pole (V = 1) to the bottom (V = 0), a fan of
/// triangles at each pole (each pole corner's U in the middle of its segment), quads split in two
/// elsewhere; exact normals of `relief` at each vertex; counter-clockwise seen from outside. With
/// `mirror_u`, U runs 0 → 1 → 0 around (the two halves share their texels, as a symmetric model's
/// mirrored UVs do).
pub fn sphere_obj_text(segments: u32, rings: u32, relief: &Relief, mirror_u: bool) -> String {
    use std::fmt::Write;
    let mut text = String::with_capacity(segments as usize * rings as usize * 120);
    let _ = writeln!(
        text,
        "# tutorial13: UV sphere, {segments} segments, {rings} rings"
    );
    let last = write_sphere_points(&mut text, segments, rings, relief);
    write_sphere_uvs(&mut text, segments, rings, mirror_u);
    write_sphere_faces(&mut text, segments, rings, last);
    text
}

/// The sphere's `v` and `vn` lines; gives their count (the bottom pole's number).
fn write_sphere_points(text: &mut String, segments: u32, rings: u32, relief: &Relief) -> u32 {
    use std::f64::consts::PI;
    use std::fmt::Write;
    // Positions and normals: the top pole, rings 1..rings-1, the bottom pole.
    let mut points = vec![(0.0, 0.0)];
    for r in 1..rings {
        for s in 0..segments {
            let phi = 2.0 * PI * s as f64 / segments as f64;
            points.push((PI * r as f64 / rings as f64, phi));
        }
    }
    points.push((PI, 0.0));
    for &(theta, phi) in &points {
        let (p, n) = relief_point(relief, sphere_direction(theta, phi));
        let _ = writeln!(text, "v {:.7} {:.7} {:.7}", p.x, p.y, p.z);
        let _ = writeln!(text, "vn {:.7} {:.7} {:.7}", n.x, n.y, n.z);
    }
    points.len() as u32
}

/// The sphere's `vt` lines.
fn write_sphere_uvs(text: &mut String, segments: u32, rings: u32, mirror_u: bool) {
    use std::fmt::Write;
    let u = |s: f64| {
        let u = s / segments as f64;
        if mirror_u {
            1.0 - (2.0 * u - 1.0).abs()
        } else {
            u
        }
    };
    // UVs: each ring's segments + 1 columns, then the poles' one per segment.
    for r in 1..rings {
        let v = 1.0 - r as f64 / rings as f64;
        for s in 0..=segments {
            let _ = writeln!(text, "vt {:.7} {v:.7}", u(s as f64));
        }
    }
    for pole_v in [1.0, 0.0] {
        for s in 0..segments {
            let _ = writeln!(text, "vt {:.7} {pole_v:.1}", u(s as f64 + 0.5));
        }
    }
}

/// The sphere's `f` lines, `last` being the bottom pole's vertex number.
fn write_sphere_faces(text: &mut String, segments: u32, rings: u32, last: u32) {
    use std::fmt::Write;
    let v = |r: u32, s: u32| match r {
        0 => 1,
        _ if r == rings => last,
        _ => 2 + (r - 1) * segments + s % segments,
    };
    let ring_vts = (rings - 1) * (segments + 1);
    let vt = |r: u32, s: u32| match r {
        0 => ring_vts + s + 1,
        _ if r == rings => ring_vts + segments + s + 1,
        _ => (r - 1) * (segments + 1) + s + 1,
    };
    let corner = |r: u32, s: u32, pole_s: u32| {
        let (pv, pt) = (
            v(r, s),
            vt(r, if r == 0 || r == rings { pole_s } else { s }),
        );
        format!("{pv}/{pt}/{pv}")
    };
    for s in 0..segments {
        // φ grows from +z towards +x: seen from outside, (r, s) → (r + 1, s) → (r + 1, s + 1) is
        // counter-clockwise.
        let _ = writeln!(
            text,
            "f {} {} {}",
            corner(0, s, s),
            corner(1, s, s),
            corner(1, s + 1, s)
        );
        for r in 1..rings - 1 {
            let (a, b, c, d) = (
                corner(r, s, s),
                corner(r + 1, s, s),
                corner(r + 1, s + 1, s),
                corner(r, s + 1, s),
            );
            let _ = writeln!(text, "f {a} {b} {c}\nf {a} {c} {d}");
        }
        let _ = writeln!(
            text,
            "f {} {} {}",
            corner(rings - 1, s, s),
            corner(rings, s, s),
            corner(rings - 1, s + 1, s)
        );
    }
}
