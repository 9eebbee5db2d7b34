//! Issue 8, items 1 and 2: OBJ index extremes and `l` lines, through the public loader.

use std::path::Path;

use tutorial13::common::objloader::{load_obj_bytes, TriangleSoup};
use tutorial13::mesh::{build_mesh, MeshOptions};
use tutorial13::Result;

fn load(text: &str) -> Result<TriangleSoup> {
    load_obj_bytes(text.as_bytes(), Path::new("mem.obj"))
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
