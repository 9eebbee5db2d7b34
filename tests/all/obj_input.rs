//! OBJ index extremes and `l` lines, through the public loader; the project's OBJ reader against
//! tobj's.

use std::path::Path;

use tutorial13::common::objloader::TriangleSoup;
use tutorial13::pipeline::obj_parse::load_obj_bytes_threaded;

use crate::differential::differ_from_tobj;
use tutorial13::assets::obj_text;
use tutorial13::mesh::{build_mesh, MeshOptions};
use tutorial13::Result;

use crate::common;

fn load(text: &str) -> Result<TriangleSoup> {
    load_obj_bytes_threaded(text.as_bytes(), Path::new("mem.obj"))
}

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n";

// Fails if an index at i64's extremes panics (negation overflow in debug), wraps past the range
// check (release), or is blamed on another kind of index than the one that is out of range.
#[test]
fn index_extremes_are_range_errors_naming_their_kind() {
    for (what, extreme) in [
        ("position", "-9223372036854775808"),
        ("position", "9223372036854775807"),
        ("UV", "-9223372036854775808"),
        ("UV", "9223372036854775807"),
        ("normal", "-9223372036854775808"),
        ("normal", "9223372036854775807"),
    ] {
        let corner = match what {
            "position" => format!("{extreme}/1/1"),
            "UV" => format!("1/{extreme}/1"),
            _ => format!("1/1/{extreme}"),
        };
        let text = format!("{TRIANGLE}f 1/1/1 2/2/1 {corner}\n");
        let e = load(&text).expect_err(&text).to_string();
        assert!(
            e.contains(&format!("{what} index {extreme} out of range")),
            "{text:?} gave {e}"
        );
    }
}

// Fails if i64::MIN as a UV index lets the face use a `vt` declared later in the file (what the
// wrapped check allowed in release builds), or if the position is blamed as "UV index 1".
#[test]
fn min_index_cannot_reach_a_later_vt() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1/-9223372036854775808/1 2/-9223372036854775808/1 3/-9223372036854775808/1\nvt 0 0\n";
    let e = load(text).unwrap_err().to_string();
    assert!(e.contains("UV index -9223372036854775808"), "{e}");

    let text = "v 0 0 0\nvn 0 0 1\nf -9223372036854775808/1/1 1/1/1 1/1/1\nvt 0 0\n";
    let e = load(text).unwrap_err().to_string();
    assert!(e.contains("position index -9223372036854775808"), "{e}");
}

// Fails if an `l` line of three or more points becomes a triangle (it has no UVs or normals, so the
// tutorial could not shade it) or reaches tobj's index arithmetic: polylines are dropped, as the
// tutorial's loader skips every line it does not know.
#[test]
fn polylines_are_dropped() {
    // Only a polyline: nothing to draw.
    let e = load("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("mem.obj") && e.contains("no faces"), "{e}");

    // A bad relative UV index in an `l` line overflowed inside tobj in debug builds.
    let e = load("v 0 0 0\nvt 0 0\nvn 0 0 1\nl 1/-3/1 1/1/1 1/1/1\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("no faces"), "{e}");

    // Beside a face, polylines change nothing, wherever they are and however they end.
    let face = format!("{TRIANGLE}f 1/1/1 2/2/1 3/3/1\n");
    let expected = load(&face).unwrap();
    for extra in [
        "l 1 2 3\n",
        "l 1 2 3 1\r\n",
        "  l\t1/1/1 2/2/1 3/3/1\n",
        "l 1/-3/1 1/1/1 1/1/1\n",
        "l 1 2",
    ] {
        for text in [format!("{face}{extra}"), format!("{extra}\n{face}")] {
            assert_eq!(load(&text).unwrap(), expected, "{text:?}");
        }
    }
    // A line that only starts with an `l` is not a polyline.
    let e = load(&format!("{face}lx 1 2 3\nf 1/1/1 2/2/1 9/3/1\n"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 10") && e.contains("position index 9"),
        "{e}"
    );
    let mesh = build_mesh(&expected, MeshOptions::default());
    assert_eq!(mesh.vertices.len(), 3);
}

/// A model as modelling tools export it, `objects` objects of `size × size` quads (a pentagon
/// closing each), each with its own `v`/`vt`/`vn` lines written just before its faces, every other
/// face in a second material, smoothing groups and comments between. `relative` writes the face
/// indices counted back from the last element (as some exporters do), else from the file's start.
fn exported_model(objects: u32, size: u32, relative: bool, normals: bool) -> String {
    use std::fmt::Write;
    let mut text = String::from("# exported\nmtllib differential.mtl\n");
    let mut declared = 0; // v, vt and vn are declared together, one of each per grid point
    for o in 0..objects {
        let _ = writeln!(text, "o Part.{o:03}\ns {}", o % 2);
        let point = |i: u32, j: u32| (o * 7 + i) as f32 * 0.25 + j as f32 * 0.001;
        for j in 0..=size {
            for i in 0..=size {
                let (x, y) = (point(i, j), j as f32 / 3.0);
                let _ = writeln!(text, "v {x:.6} {y:.6} {:.6}", (x * y).sin());
                let _ = writeln!(text, "vt {:.6} {:.6}", i as f32 / size as f32, y / 7.0);
                let _ = writeln!(text, "vn {:.4} 0.7071 {:.4}", x.cos() * 0.7, x.sin() * 0.7);
            }
        }
        let first = declared + 1;
        declared += (size + 1) * (size + 1);
        let corner = |i: u32, j: u32| {
            let index = first + j * (size + 1) + i;
            let index = match relative {
                true => index as i64 - declared as i64 - 1,
                false => index as i64,
            };
            match normals {
                true => format!("{index}/{index}/{index}"),
                false => format!("{index}/{index}"),
            }
        };
        for j in 0..size {
            for i in 0..size {
                let material = if (i + j) % 2 == 0 { "Brick" } else { "Paint" };
                let _ = writeln!(
                    text,
                    "usemtl {material}\nf {} {} {} {}",
                    corner(i, j),
                    corner(i + 1, j),
                    corner(i + 1, j + 1),
                    corner(i, j + 1)
                );
            }
        }
        let _ = writeln!(
            text,
            "f {} {} {} {} {}",
            corner(0, 0),
            corner(size, 0),
            corner(size, size),
            corner(size / 2, size),
            corner(0, size)
        );
    }
    text
}

const DIFFERENTIAL_MTL: &[u8] =
    b"newmtl Brick\nKd 0.8 0.2 0.1\nmap_Kd brick.png\nnewmtl Paint\nKd 0.1 0.2 0.9\n";

fn assert_same_as_tobj(what: &str, text: &[u8]) {
    if let Err(difference) = differ_from_tobj(text, DIFFERENTIAL_MTL) {
        panic!("{what}: {difference}");
    }
}

// Fails if the project's OBJ reader gives any file generated here another soup (to the bit), other
// materials or another error than tobj's parse with the checks: large files read on several cores
// (absolute and relative indices, several objects, materials, quads and polygons), the tutorial's
// own cylinder, and small files at every edge tobj and the checks draw.
#[test]
fn the_obj_reader_reads_as_tobj_does() {
    let large = [
        (
            "grid cylinder",
            obj_text::grid_cylinder_obj_text(400, 100, 1.0, 2.0, 1.0),
        ),
        (
            "charted cylinder",
            obj_text::charted_cylinder_obj_text(300, 100, 1.0, 2.0, 8),
        ),
        ("exported", exported_model(30, 40, false, true)),
        (
            "exported, relative indices",
            exported_model(30, 40, true, true),
        ),
        ("exported, no normals", exported_model(30, 40, false, false)),
        (
            "tutorial's cylinder",
            obj_text::tutorial_cylinder_obj_text(12),
        ),
    ];
    for (what, text) in &large {
        assert_same_as_tobj(what, text.as_bytes());
        assert_same_as_tobj(what, text.replace('\n', "\r\n").as_bytes());
    }
    // Several cores read a file of a few megabytes in pieces: the relative one has to be
    // large enough for a piece to start without its counts.
    assert!(large[3].1.len() > 3 << 20, "{} bytes", large[3].1.len());
    if let Some(dir) = common::original_assets("the_obj_reader_reads_as_tobj_does") {
        assert_same_as_tobj(
            "original",
            &std::fs::read(dir.join("cylinder.obj")).unwrap(),
        );
    }

    let small = exported_model(2, 2, false, true);
    let edits = [
        ("v 0.000000", "v 1 2 3 0.5\nv 0.000000"),
        ("v 0.000000", "v 1 2 3 0\nv 0.000000"),
        ("v 0.000000", "v 1 2 3 0.5 0.5 0.5\nv 0.000000"),
        ("v 0.000000", "v 1 2 3 0.5 x 0.5\nv 0.000000"),
        ("v 0.000000", "v 1 2 3 0.5 0.5\nv 0.000000"),
        ("v 0.000000", "v 1 2 3 4 5 6 7\nv 0.000000"),
        ("v 0.000000", "v 1 2\nv 0.000000"),
        ("v 0.000000", "v nan 2 3\nv 0.000000"),
        ("v 0.000000", "v\u{a0}0.000000"),
        ("v 0.000000", "v\u{0b}0.000000"),
        ("v 0.000000", "v\t0.000000"),
        ("v 0.000000", "v 1e39"),
        ("vt 0.000000", "vt 0.000000 0.5 0.5\nvt 0.000000"),
        ("vt 0.000000", "vt inf"),
        ("vn ", "vn 1 2\nvn "),
        ("f 1/1/1", "f +1/1/1"),
        ("f 1/1/1", "f 1//1"),
        ("f 1/1/1", "f 1/1/"),
        ("f 1/1/1", "f /1/1"),
        ("f 1/1/1", "f 1/1/1/"),
        ("f 1/1/1", "f 0/1/1"),
        ("f 1/1/1", "f 99/1/1"),
        ("f 1/1/1", "f -99/1/1"),
        ("f 1/1/1", "f 00000000000000000001/1/1"),
        ("f 1/1/1", "f 99999999999999999999/1/1"),
        ("f 1/1/1", "l 1/1/1"),
        ("f 1/1/1", "p 1/1/1"),
        ("f 1/1/1", "f\u{2003}1/1/1"),
        ("f 1/1/1", "f  1/1/1"),
        ("f 1/1/1", "#f 1/1/1"),
        ("usemtl Brick", "usemtl\tBrick"),
        ("usemtl Brick", "usemtl Brick \u{a0}"),
        ("usemtl Brick", "usemtl   "),
        ("usemtl Brick", "usemtl Unknown"),
        ("usemtl Brick", "usemtl  Paint"),
        ("mtllib differential.mtl", "mtllib\tdifferential.mtl"),
        (
            "mtllib differential.mtl",
            "mtllib a b.mtl\nmtllib differential.mtl",
        ),
        ("mtllib differential.mtl", ""),
        ("o Part.000", "o Part.000\r"),
        ("o Part.000", "g"),
        ("\n", "\n\n#\n"),
    ];
    for (from, to) in edits {
        assert!(small.contains(from), "{from:?}");
        // Every place the text occurs, one at a time.
        for (at, _) in small.match_indices(from) {
            let text = format!("{}{to}{}", &small[..at], &small[at + from.len()..]);
            assert_same_as_tobj(&format!("{from:?} → {to:?} at {at}"), text.as_bytes());
        }
    }
    // Vertex colours on every `v` line, and on the used ones only (which tobj reads too).
    let coloured = "mtllib m.mtl\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nvt 0 0\nvn 0 0 1\n\
                    usemtl Paint\nf 1/1/1 2/1/1 3/1/1\n";
    let partly = format!("{coloured}v 5 5 5\nf 1/1/1 2/1/1 3/1/1\n");
    let past = format!("{coloured}v 5 5 5\nf 1/1/1 2/1/1 4/1/1\n");
    for text in [coloured, &partly, &past] {
        assert_same_as_tobj(text, text.as_bytes());
    }
    for text in [
        "",
        "\n",
        "v 0 0 0\n",
        "f 1/1/1 1/1/1 1/1/1\n",
        "\u{feff}v 0 0 0",
    ] {
        assert_same_as_tobj(text, text.as_bytes());
    }
}

/// How a sculpt's face corners name their elements (none names a UV).
#[derive(Clone, Copy, Debug)]
enum SculptCorners {
    /// `v//vn`, as ZBrush and Blender write a sculpt with normals.
    PositionNormal,
    /// `v`: no normals (they are computed).
    Position,
    /// `v/` and `v//`, which some exporters write for `v`.
    Slashes,
}

/// A sculpt as sculpting tools export it: `parts` objects, each a bumpy sphere of `rings × segments`
/// (quads, triangles at the poles), its `v` and `vn` lines before its faces, no `vt` and no UV in
/// any corner. `relative` writes the indices counted back from the last element declared.
fn sculpt_obj(
    parts: u32,
    rings: u32,
    segments: u32,
    corners: SculptCorners,
    relative: bool,
) -> String {
    use std::fmt::Write;
    let mut text = String::from("# sculpt, no UV layout\n");
    let mut declared = 0i64; // v and vn are declared together, one of each per point
    for part in 0..parts {
        let _ = writeln!(text, "o Sculpt.{part:03}");
        let first = declared + 1;
        let mut point = |theta: f64, phi: f64| {
            let direction = [
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ];
            let r = 1.0 + 0.05 * (7.0 * theta).sin() * (5.0 * phi).cos();
            let [x, y, z] = direction.map(|d| d * r);
            let _ = writeln!(text, "v {:.6} {:.6} {:.6}", x + 3.0 * part as f64, y, z);
            let [a, b, c] = direction;
            let _ = writeln!(text, "vn {a:.6} {b:.6} {c:.6}");
            declared += 1;
        };
        use std::f64::consts::PI;
        point(0.0, 0.0);
        for r in 1..rings {
            for s in 0..segments {
                point(
                    PI * r as f64 / rings as f64,
                    2.0 * PI * s as f64 / segments as f64,
                );
            }
        }
        point(PI, 0.0);
        let last = declared;
        let corner = |k: i64| {
            let index = if relative { k - declared - 1 } else { k };
            match (corners, k % 2) {
                (SculptCorners::PositionNormal, _) => format!("{index}//{index}"),
                (SculptCorners::Position, _) => format!("{index}"),
                (SculptCorners::Slashes, 0) => format!("{index}/"),
                (SculptCorners::Slashes, _) => format!("{index}//"),
            }
        };
        let at = |r: u32, s: u32| first + 1 + ((r - 1) * segments + s % segments) as i64;
        for s in 0..segments {
            let _ = writeln!(
                text,
                "f {} {} {}",
                corner(first),
                corner(at(1, s + 1)),
                corner(at(1, s))
            );
        }
        for r in 1..rings - 1 {
            for s in 0..segments {
                let quad = [at(r, s), at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)];
                let _ = writeln!(text, "f {}", quad.map(corner).join(" "));
            }
        }
        for s in 0..segments {
            let pole = corner(last);
            let _ = writeln!(
                text,
                "f {} {} {pole}",
                corner(at(rings - 1, s)),
                corner(at(rings - 1, s + 1))
            );
        }
    }
    text
}

// Fails if a sculpt without UVs read as a bake's HIGH (`load_shape_bytes`, one pass) differs in
// any bit, notice, material or placement from what the rewrite read before (`vt 0 0` added and
// every corner pointed at it, then read as a model): `v//vn`, `v`, `v/` and `v//` corners, quads
// and triangles, absolute and negative indices, one part and several, large enough to be read on
// several cores; if a file with only some corners naming a UV is not refused with the model's own
// line; or if a model that needs UVs (`load_model_bytes`) takes a sculpt.
#[test]
fn a_sculpt_is_read_in_one_pass_as_its_rewrite_was() {
    use crate::differential::shape_differs_from_rewrite;
    use tutorial13::model::{load_model_bytes, MapOverrides};
    let path = Path::new("sculpt.obj");
    let nothing = |_: &Path| Err(std::io::ErrorKind::NotFound.into());
    let model =
        |text: &str| load_model_bytes(text.as_bytes(), path, &MapOverrides::default(), nothing);
    let cases = [
        (1, 180, 360, SculptCorners::PositionNormal, false),
        (1, 180, 360, SculptCorners::PositionNormal, true),
        (3, 20, 40, SculptCorners::Position, true),
        (2, 12, 24, SculptCorners::Slashes, false),
    ];
    for (parts, rings, segments, corners, relative) in cases {
        let what =
            format!("{parts} part(s), {rings} × {segments}, {corners:?}, relative {relative}");
        let text = sculpt_obj(parts, rings, segments, corners, relative);
        let read = shape_differs_from_rewrite(text.as_bytes(), path, nothing);
        read.unwrap_or_else(|e| panic!("{what}: {e}")).expect(&what);
        // A model needs UVs: its refusal names the first corner without one.
        let refusal = model(&text).expect_err(&what).to_string();
        assert!(
            refusal.contains("needs a texture coordinate index"),
            "{what}: {refusal}"
        );
        assert_same_as_tobj(&what, text.as_bytes());
    }
    assert!(sculpt_obj(1, 180, 360, SculptCorners::PositionNormal, true).len() > 3 << 20);

    // Some corners with a UV, some without: refused as the model refuses it (the rewrite took
    // none of it), wherever the corners without are.
    let uvs = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
    for faces in [
        "f 1/1/1 2/1/1 3/1/1\nf 1//1 2//1 3//1\n",
        "f 1//1 2//1 3//1\nf 1/1/1 2/1/1 3/1/1\n",
        "f 1/1/1 2//1 3/1/1\n",
        "f 1/1 2 3\n",
    ] {
        let text = format!("{uvs}{faces}");
        let read = shape_differs_from_rewrite(text.as_bytes(), path, nothing);
        read.unwrap_or_else(|e| panic!("{text}: {e}"))
            .expect_err(&text);
        assert_same_as_tobj(&text, text.as_bytes());
    }
}
