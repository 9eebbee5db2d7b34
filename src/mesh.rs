//! The CPU half of `tutorial13.cpp`'s set-up, in its order: `loadOBJ`, `computeTangentBasis`,
//! `indexVBO_TBN`. Its options are the tutorial's experiments, so a switch re-runs only this part.
//!
//! The code that runs is the tutorial's own ports in [`crate::common`] for a mesh of the tutorial's
//! size, so that what a learner reads (and edits, for the first exercise) is what draws; their fast
//! twins in [`crate::pipeline`], which give the same results to the bit, take over above
//! [`PORTS_UP_TO_TRIANGLES`] triangles (an OBJ file above [`PORTS_UP_TO_OBJ_BYTES`]), where the
//! tutorial's quadratic search would keep a learner's model waiting (BENCHMARKS.md, "The ports or
//! their twins").

use std::path::Path;

use crate::common::objloader::{load_obj, TriangleSoup};
use crate::common::tangentspace::{compute_tangent_basis, TangentBasis, TangentOptions};
use crate::common::vboindexer::{index_vbo_tbn, IndexOptions, IndexedMesh};
use crate::pipeline::indexer::index_vbo_tbn_hashed;
use crate::pipeline::obj_parse::load_obj_threaded;
use crate::Result;

/// Every switch of the CPU pipeline.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MeshOptions {
    pub tangents: TangentOptions,
    pub indexing: IndexOptions,
    /// The code that reads and indexes: `None` chooses by size (the ports up to
    /// [`PORTS_UP_TO_TRIANGLES`], the twins above); `Some` runs that one whatever the size (the
    /// exercise check's reference is built by the twins, which a learner's edit of a port leaves as
    /// they are).
    pub code: Option<Code>,
}

/// The most triangles a soup may have for the tutorial's `indexVBO_TBN` port to index it. Its
/// search is quadratic: measured (BENCHMARKS.md), 0.015 ms at the tutorial's 64 triangles, 1.6 ms
/// at 1 024, 28 ms at 4 096, 146 ms at 10 240, against 0.25, 1.25 and 3.3 ms for the hash grid.
/// At 2 048 it costs a few milliseconds once, at load: nothing a learner waits for.
pub const PORTS_UP_TO_TRIANGLES: usize = 2048;

/// The largest OBJ file the tutorial's `loadOBJ` port reads: 128 KiB, about 2 000 triangles as
/// the tools write them (65 bytes a triangle for the benchmarks' cylinders), read in 1.5 ms by
/// tobj on one core where the parse on every core takes 0.6 ms (1 024 triangles, BENCHMARKS.md).
pub const PORTS_UP_TO_OBJ_BYTES: u64 = 128 * 1024;

/// The code that runs a step of the CPU pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Code {
    /// The tutorial's own, ported: [`load_obj`], [`index_vbo_tbn`] (src/common/).
    Ports,
    /// The same results to the bit, fast: [`load_obj_threaded`], [`index_vbo_tbn_hashed`]
    /// (src/pipeline/).
    FastTwins,
}

impl Code {
    /// Where the code is, for the log.
    pub fn place(self) -> &'static str {
        match self {
            Code::Ports => "the ports in src/common/",
            Code::FastTwins => "the fast twins in src/pipeline/",
        }
    }

    /// `choice`, or the code for `size` against `most` (the ports up to it).
    fn by_size(choice: Option<Code>, size: u64, most: u64) -> Code {
        choice.unwrap_or(if size <= most {
            Code::Ports
        } else {
            Code::FastTwins
        })
    }
}

/// Which code built a mesh: its OBJ read (`None` for a soup read another way, a learner's model)
/// and its indexing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BuiltBy {
    pub load_obj: Option<Code>,
    pub index_vbo_tbn: Code,
}

impl std::fmt::Display for BuiltBy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let index = self.index_vbo_tbn.place();
        match self.load_obj {
            Some(load) if load == self.index_vbo_tbn => {
                write!(
                    f,
                    "loadOBJ, computeTangentBasis and indexVBO_TBN ran as {index}"
                )
            }
            Some(load) => write!(
                f,
                "loadOBJ ran as {}, computeTangentBasis as the port, indexVBO_TBN as {index}",
                load.place()
            ),
            None => write!(
                f,
                "computeTangentBasis ran as the port, indexVBO_TBN as {index}"
            ),
        }
    }
}

/// `loadOBJ`: the port ([`load_obj`]) for a file up to [`PORTS_UP_TO_OBJ_BYTES`], else its twin
/// ([`load_obj_threaded`]), unless `choice` names one.
pub fn load_obj_by_size(path: &Path, choice: Option<Code>) -> Result<(TriangleSoup, Code)> {
    // A file that cannot be read is the port's to report (the twin reports it the same way).
    let bytes = std::fs::metadata(path).map_or(0, |m| m.len());
    let code = Code::by_size(choice, bytes, PORTS_UP_TO_OBJ_BYTES);
    let soup = match code {
        Code::Ports => load_obj(path)?,
        Code::FastTwins => load_obj_threaded(path)?,
    };
    Ok((soup, code))
}

/// `indexVBO_TBN`: the port ([`index_vbo_tbn`]) for a soup of up to [`PORTS_UP_TO_TRIANGLES`]
/// triangles, else its twin ([`index_vbo_tbn_hashed`]), unless `options` name one.
pub fn index_vbo_tbn_by_size(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: MeshOptions,
) -> (IndexedMesh, Code) {
    let triangles = soup.triangle_count() as u64;
    let code = Code::by_size(options.code, triangles, PORTS_UP_TO_TRIANGLES as u64);
    let mesh = match code {
        Code::Ports => index_vbo_tbn(soup, basis, options.indexing),
        Code::FastTwins => index_vbo_tbn_hashed(soup, basis, options.indexing),
    };
    (mesh, code)
}

/// Soup → tangents → indexed mesh.
pub fn build_mesh(soup: &TriangleSoup, options: MeshOptions) -> IndexedMesh {
    let basis = compute_tangent_basis(soup, options.tangents);
    index_vbo_tbn_by_size(soup, &basis, options).0
}

/// OBJ text of an open cylinder around the y axis (sides only, smooth radial normals) of any size:
/// `segments` around, `rings` bands from y = 0 to y = `height`, U wrapping the texture `u_repeat`
/// times around (growing to the right seen from outside) and V running 0..1 upwards. Faces are
/// counter-clockwise seen from outside. The seam repeats its positions' UVs at U = `u_repeat`, as the
/// tutorial's file does, so indexing keeps two vertices there.
///
/// Used for the benchmarks' large meshes and for tests that need rings or odd UV scales; the project's
/// `assets/cylinder.obj` comes from [`crate::assets::tutorial_cylinder_obj_text`], which follows the
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
