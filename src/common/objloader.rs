//! `common/objloader.cpp`: read an OBJ into the tutorial's de-indexed triangle soup.
//!
//! The tutorial's `loadOBJ` reads `v`, `vt`, `vn` and `f a/b/c a/b/c a/b/c`, then emits three
//! corners per triangle (position, UV, normal), negating V because its textures are DDS files stored
//! upside down. Here tobj reads the file (polygons triangulated, negative indices resolved) and the
//! checks add what tobj patches over silently: a face corner without UV or normal (tobj reuses the
//! previous one), index 0 or out-of-range relative indices. The tutorial's cylinder is read here; a
//! file above [`crate::mesh::PORTS_UP_TO_OBJ_BYTES`] is read by [`crate::pipeline::obj_parse`], the
//! same soup to the bit on every core, which leaves the files it refuses to [`read_obj`] here, so
//! that one set of errors is reported.

use std::path::Path;

use glam::{Vec2, Vec3};

use crate::{Error, Result};

/// Three corners per triangle, in file order, as `loadOBJ`'s three output vectors.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriangleSoup {
    pub vertices: Vec<Vec3>,
    /// `(u, -v)`: V negated exactly as the tutorial's loader does.
    pub uvs: Vec<Vec2>,
    pub normals: Vec<Vec3>,
}

impl TriangleSoup {
    pub fn triangle_count(&self) -> usize {
        self.vertices.len() / 3
    }
}

/// Reads `path` as the tutorial's `loadOBJ` does. Errors name the file and the reason.
pub fn load_obj(path: &Path) -> Result<TriangleSoup> {
    let bytes = crate::files::read(path).map_err(|e| Error::io(path, e))?;
    load_obj_bytes(&bytes, path)
}

/// [`load_obj`] on bytes already in memory; `path` is only used in error messages.
pub fn load_obj_bytes(bytes: &[u8], path: &Path) -> Result<TriangleSoup> {
    Ok(read_obj(bytes, path, ObjMode::Tutorial, no_materials)?.soup)
}

/// The `.mtl` loader of the tutorial's mode: it never touches the file.
pub fn no_materials(_: &Path) -> tobj::MTLLoadResult {
    Ok((Vec::new(), Default::default()))
}

/// How [`read_obj`] reads a file: as the tutorial's `loadOBJ`, or as a learner's model (the
/// project's addition, `crate::model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObjMode {
    /// V negated, every corner `v/vt/vn`, the `.mtl` never read.
    Tutorial,
    /// V as written, corners `v/vt` or `v/vt/vn` (normals left out are computed by the caller), the
    /// `.mtl` read through the material loader.
    Model,
    /// As [`ObjMode::Model`] for a model whose UVs are never used (a bake's HIGH, often a sculpt
    /// exported without them): a file none of whose corners names a UV (`v`, `v//vn`) is read with
    /// (0, 0) at every corner; one where only some corners do is refused as [`ObjMode::Model`]
    /// refuses it.
    Shape,
}

/// What [`read_obj`] reads: the soup, and for [`ObjMode::Model`] each triangle's material.
#[derive(Debug, Default)]
pub struct ObjRead {
    pub soup: TriangleSoup,
    /// One per triangle: an index into `materials`, or `None` (no `usemtl`, or an unknown one).
    pub triangle_materials: Vec<Option<usize>>,
    pub materials: Vec<tobj::Material>,
    /// Only when `normals_missing`: each corner's position index in the file (the key of a smooth
    /// normal); empty otherwise, so that the tutorial's loads carry no extra array.
    pub position_indices: Vec<u32>,
    /// No corner has a normal index: `soup.normals` is empty, for the caller to compute.
    pub normals_missing: bool,
    /// [`ObjMode::Shape`] only: no corner names a UV, and `soup.uvs` is (0, 0) at every corner.
    pub uvs_missing: bool,
}

pub(crate) fn obj_error(path: &Path, reason: String) -> Error {
    Error::Obj {
        path: path.to_path_buf(),
        reason,
    }
}

pub(crate) fn utf8<'b>(bytes: &'b [u8], path: &Path) -> Result<&'b str> {
    std::str::from_utf8(bytes)
        .map_err(|e| obj_error(path, format!("not UTF-8 text (byte {})", e.valid_up_to())))
}

/// Reads an OBJ in either mode: tobj's parse with the checks below it. `materials` loads an
/// `mtllib` (called with the name as written in the OBJ). The reference the program's parse
/// ([`crate::pipeline::obj_parse`]) is tested against, and the reader of the files it refuses.
pub fn read_obj(
    bytes: &[u8],
    path: &Path,
    mode: ObjMode,
    materials: impl Fn(&Path) -> tobj::MTLLoadResult,
) -> Result<ObjRead> {
    let text = utf8(bytes, path)?;
    if mode == ObjMode::Shape && names_a_uv(text) {
        // Some corner has a UV: every corner needs one, and the errors are a model's.
        return read_obj(bytes, path, ObjMode::Model, materials);
    }
    let uvs_missing = mode == ObjMode::Shape;
    let err = |reason: String| obj_error(path, reason);
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // The face check and tobj's parse read the same text: they run on both cores (a quarter of a
    // large file's load), and tobj's result is used only once the check has passed. A panic in tobj
    // on a file the check refuses is caught, so that the check's error is what the user sees.
    let (scan, parsed) = beside(
        || check_faces(text, mode),
        || {
            // tobj reads `l` lines with its face parser, so a polyline of three or more points would
            // become a triangle. The tutorial's loader skips lines it does not know, `l` included: drop
            // them here, keeping the line count so that tobj's view of the file is otherwise the same.
            let text = if has_polylines(text) {
                std::borrow::Cow::Owned(drop_polylines(text))
            } else {
                std::borrow::Cow::Borrowed(text)
            };
            // The tutorial never touches the .mtl file: its caller passes a loader that reads nothing.
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                tobj::load_obj_buf(&mut text.as_bytes(), &options, &materials)
            }))
        },
    );
    let scan = scan.map_err(err)?;
    let (models, loaded) = parsed
        .ok_or_else(|| err("the face check failed".into()))?
        .map_err(|_| err("tobj's parser panicked".into()))?
        .map_err(|e| err(e.to_string()))?;

    let normals_missing = mode != ObjMode::Tutorial && scan.corners_with_normal == 0;
    let mut read = ObjRead {
        materials: loaded.unwrap_or_default(),
        normals_missing,
        uvs_missing,
        ..Default::default()
    };
    let soup = &mut read.soup;
    for model in &models {
        let mesh = &model.mesh;
        // The pre-scan guarantees that every corner has its indices, so the index lists match.
        let normals_match = normals_missing || mesh.normal_indices.len() == mesh.indices.len();
        let uvs_match = uvs_missing || mesh.texcoord_indices.len() == mesh.indices.len();
        if !uvs_match || !normals_match {
            return Err(err(format!(
                "object '{}' has faces without UV or normal indices",
                model.name
            )));
        }
        for (corner, &vi) in mesh.indices.iter().enumerate() {
            let vi = vi as usize;
            let position = Vec3::from_slice(&mesh.positions[3 * vi..3 * vi + 3]);
            let uv = match uvs_missing {
                true => Vec2::ZERO,
                false => {
                    let ti = mesh.texcoord_indices[corner] as usize;
                    Vec2::from_slice(&mesh.texcoords[2 * ti..2 * ti + 2])
                }
            };
            let normal = match normals_missing {
                true => Vec3::ZERO,
                false => {
                    let ni = mesh.normal_indices[corner] as usize;
                    Vec3::from_slice(&mesh.normals[3 * ni..3 * ni + 3])
                }
            };
            if !(position.is_finite() && uv.is_finite() && normal.is_finite()) {
                return Err(err(format!(
                    "object '{}' uses a non-finite number (position {position}, uv {uv}, normal {normal})",
                    model.name
                )));
            }
            soup.vertices.push(position);
            soup.uvs.push(match mode {
                // Invert V: the tutorial's DDS textures are stored upside down.
                ObjMode::Tutorial => Vec2::new(uv.x, -uv.y),
                ObjMode::Model | ObjMode::Shape => uv,
            });
            if normals_missing {
                // tobj numbers positions per object and material, not in the file: this key is
                // only right within one of them (the project's reader gives the file's index).
                read.position_indices.push(vi as u32);
            } else {
                soup.normals.push(normal);
            }
        }
        let triangles = mesh.indices.len() / 3;
        read.triangle_materials
            .extend(std::iter::repeat_n(mesh.material_id, triangles));
    }
    if read.soup.vertices.is_empty() {
        return Err(err("no faces".into()));
    }
    Ok(read)
}

/// What [`check_faces`] saw besides errors.
struct FaceScan {
    corners_with_normal: usize,
    corners_without_normal: usize,
}

/// Whether some corner of an `f` line names a UV (`v/vt`, `v/vt/vn`).
fn names_a_uv(text: &str) -> bool {
    text.lines().any(|line| {
        let mut words = line.split_whitespace();
        words.next() == Some("f")
            && words.any(|corner| corner.split('/').nth(1).is_some_and(|vt| !vt.is_empty()))
    })
}

/// Checks every `f` line for what the tutorial needs and tobj does not enforce: at least three
/// corners, each written `v/vt/vn` with all three indices present, non-zero and in range at that
/// point of the file (relative indices count back from the elements declared so far); in
/// [`ObjMode::Model`] the normal index may be left out, by every corner or by none; in
/// [`ObjMode::Shape`] (called only when no corner names a UV) the UV index too. Returns how many
/// corners have a normal index.
fn check_faces(text: &str, mode: ObjMode) -> std::result::Result<FaceScan, String> {
    let mut scan = FaceScan {
        corners_with_normal: 0,
        corners_without_normal: 0,
    };
    let mut counts = [0usize; 3]; // v, vt, vn declared so far
    for (line_number, line) in text.lines().enumerate() {
        let line_number = line_number + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f") => {
                let mut corners = 0;
                for corner in words {
                    let has_normal = check_corner(corner, &counts, mode).map_err(|reason| {
                        format!("line {line_number}: corner '{corner}': {reason}")
                    })?;
                    match has_normal {
                        true => scan.corners_with_normal += 1,
                        false => scan.corners_without_normal += 1,
                    }
                    corners += 1;
                }
                if corners < 3 {
                    return Err(format!(
                        "line {line_number}: a face needs at least 3 corners, found {corners}"
                    ));
                }
            }
            _ => {}
        }
    }
    if scan.corners_with_normal > 0 && scan.corners_without_normal > 0 {
        // tobj would fill the missing ones with other corners' normals.
        return Err(format!(
            "{} face corners have a normal index and {} have none: give every corner one \
             (v/vt/vn) or none (v/vt, and normals are computed)",
            scan.corners_with_normal, scan.corners_without_normal
        ));
    }
    Ok(scan)
}

/// Whether any line of `text` is an `l` (polyline) line, as [`drop_polylines`] finds them.
fn has_polylines(text: &str) -> bool {
    text.split('\n').any(|line| {
        line.trim_start().starts_with('l') && line.split_whitespace().next() == Some("l")
    })
}

/// `text` with every `l` line emptied (its line break kept). Lines are split as tobj splits them
/// (on `\n`; a `\r` before it is whitespace to both).
fn drop_polylines(text: &str) -> String {
    let mut kept = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        if line.split_whitespace().next() == Some("l") {
            if line.ends_with('\n') {
                kept.push('\n');
            }
        } else {
            kept.push_str(line);
        }
    }
    kept
}

/// Checks one face corner; returns whether it has a normal index.
fn check_corner(
    corner: &str,
    counts: &[usize; 3],
    mode: ObjMode,
) -> std::result::Result<bool, String> {
    const WHAT: [&str; 3] = ["position", "UV", "normal"];
    let needs = match mode {
        ObjMode::Tutorial => NEEDS_UV_AND_NORMAL,
        ObjMode::Model | ObjMode::Shape => NEEDS_UV,
    };
    let mut parts = corner.split('/');
    let parts = [parts.next(), parts.next(), parts.next(), parts.next()];
    let (v, vt, vn) = match parts {
        [Some(v), Some(vt), Some(vn), None] => (v, vt, vn),
        [Some(v), Some(vt), None, None] if mode != ObjMode::Tutorial => (v, vt, ""),
        [Some(v), None, None, None] if mode == ObjMode::Shape => (v, "", ""),
        _ => return Err(needs.into()),
    };
    if (vt.is_empty() && mode != ObjMode::Shape) || (vn.is_empty() && mode == ObjMode::Tutorial) {
        return Err(needs.into());
    }
    for (k, part) in [v, vt, vn].into_iter().enumerate() {
        if part.is_empty() {
            continue; // a model's missing normal, a shape's missing UV
        }
        let index: i64 = part
            .parse()
            .map_err(|_| format!("'{part}' is not an index"))?;
        // Compared without negating `index`: -i64::MIN overflows, and once wrapped it passed the
        // check and let tobj's own index arithmetic wrap into a later element.
        let count = i64::try_from(counts[k]).unwrap_or(i64::MAX);
        let in_range = if index > 0 {
            index <= count
        } else {
            index < 0 && index >= -count
        };
        if !in_range {
            return Err(format!(
                "{} index {index} out of range ({count} declared so far)",
                WHAT[k]
            ));
        }
    }
    Ok(!vn.is_empty())
}

const NEEDS_UV_AND_NORMAL: &str = "needs a UV and a normal index (v/vt/vn): the tutorial uses both";
const NEEDS_UV: &str = "needs a texture coordinate index (v/vt or v/vt/vn): normal mapping reads \
                        its maps at each point's UV, and the model has none there";

/// `check` on another core while `parse` runs here. In the browser (wasm32: no threads, and a panic
/// aborts rather than being caught) `parse` runs after `check` and only if it passed, so `None`
/// there means the check failed. A panic in `check` reads as a failed check.
fn beside<C: Send, P>(
    check: impl FnOnce() -> std::result::Result<C, String> + Send,
    parse: impl FnOnce() -> P,
) -> (std::result::Result<C, String>, Option<P>) {
    #[cfg(target_arch = "wasm32")]
    return {
        let scan = check();
        let parsed = scan.is_ok().then(parse);
        (scan, parsed)
    };
    #[cfg(not(target_arch = "wasm32"))]
    return std::thread::scope(|scope| {
        let checker = scope.spawn(check);
        let parsed = Some(parse());
        let scan = checker
            .join()
            .unwrap_or_else(|_| Err("the face check failed".into()));
        (scan, parsed)
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(text: &str) -> Result<TriangleSoup> {
        load_obj_bytes(text.as_bytes(), Path::new("mem.obj"))
    }

    const QUAD: &str =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n";

    // Fails if quads are not triangulated into two triangles or V is not negated.
    #[test]
    fn quad_is_triangulated_and_v_negated() {
        let soup = load(&format!("{QUAD}f 1/1/1 2/2/1 3/3/1 4/4/1\n")).unwrap();
        assert_eq!(soup.triangle_count(), 2);
        assert_eq!(soup.vertices[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(soup.uvs[2], Vec2::new(1.0, -1.0));
        assert!(soup.normals.iter().all(|&n| n == Vec3::Z));
    }

    // Fails if relative (negative) indices are not resolved against the elements declared so far.
    #[test]
    fn negative_indices_match_positive_ones() {
        let a = load(&format!("{QUAD}f 1/1/1 2/2/1 3/3/1\n")).unwrap();
        let b = load(&format!("{QUAD}f -4/-4/-1 -3/-3/-1 -2/-2/-1\n")).unwrap();
        assert_eq!(a, b);
    }

    // Fails if a bad input is accepted, or its error does not name the file and the reason.
    #[test]
    fn bad_inputs_are_errors_naming_the_file() {
        let cases = [
            (String::from("v 0 0 0\n"), "no faces"),
            (format!("{QUAD}f 1 2 3\n"), "needs a UV and a normal"),
            (
                format!("{QUAD}f 1//1 2//1 3//1\n"),
                "needs a UV and a normal",
            ),
            (format!("{QUAD}f 1/1 2/2 3/3\n"), "needs a UV and a normal"),
            (format!("{QUAD}f 1/1/1 2/2/1 9/3/1\n"), "out of range"),
            (format!("{QUAD}f 1/1/1 2/2/1 0/3/1\n"), "out of range"),
            (format!("{QUAD}f 1/1/1 2/2/1 -5/3/1\n"), "out of range"),
            (format!("{QUAD}f 1/1/1 2/2/2 3/3/1\n"), "out of range"),
            (
                format!("{QUAD}f 1/1/1 2/2/1 -99999999999999999999/3/1\n"),
                "not an index",
            ),
            (format!("{QUAD}f 1/1/1 2/2/1\n"), "at least 3 corners"),
            (format!("{QUAD}f 1/1/1 2/x/1 3/3/1\n"), "not an index"),
            (
                "v 0 0 nan\nvt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n".into(),
                "non-finite",
            ),
            (
                "v 0 0 1e39\nvt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n".into(),
                "non-finite",
            ),
            (
                "v 0 0 0\nvt 0 inf\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n".into(),
                "non-finite",
            ),
            (
                "v 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n".into(),
                "mem.obj",
            ),
            (
                "v 0 0 zero\nvt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n".into(),
                "mem.obj",
            ),
        ];
        for (text, reason) in cases {
            let e = load(&text).expect_err(&text).to_string();
            assert!(e.starts_with("mem.obj: malformed OBJ"), "{e}");
            assert!(e.contains(reason), "{text:?} gave {e}");
        }
        let e = load_obj_bytes(b"v 0 0 0\n\xff\xfe", Path::new("mem.obj")).unwrap_err();
        assert!(e.to_string().contains("not UTF-8"), "{e}");
    }

    // Fails if a missing file panics or its error does not name the file.
    #[test]
    fn missing_file_names_the_file() {
        let e = load_obj(Path::new("/nonexistent/cylinder.obj")).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/cylinder.obj"), "{e}");
    }

    const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0.25\nvt 1 0\nvt 0 1\nvn 0 0 1\n";

    // Fails if a model whose faces are all `v/vt` is not read with its normals left to compute:
    // `normals_missing`, no normals, each corner's position index kept, V as written (not
    // negated), one material slot per triangle.
    #[test]
    fn model_faces_without_normals_leave_them_to_compute() {
        let text = format!("{TRIANGLE}f 1/1 2/2 3/3\n");
        let read = read_obj(
            text.as_bytes(),
            Path::new("m.obj"),
            ObjMode::Model,
            no_materials,
        )
        .unwrap();
        assert!(read.normals_missing);
        assert!(read.soup.normals.is_empty());
        assert_eq!(read.position_indices, [0, 1, 2]);
        assert_eq!(read.soup.uvs, [Vec2::new(0.0, 0.25), Vec2::X, Vec2::Y]);
        assert_eq!(read.triangle_materials, [None]);
    }

    // Fails if a model whose faces all have normals is read as one without (or a tutorial file as
    // a model): its normals are the file's and no position indices are kept.
    #[test]
    fn model_faces_with_normals_keep_them() {
        let text = format!("{TRIANGLE}f 1/1/1 2/2/1 3/3/1\n");
        for mode in [ObjMode::Model, ObjMode::Tutorial] {
            let read = read_obj(text.as_bytes(), Path::new("m.obj"), mode, no_materials).unwrap();
            assert!(!read.normals_missing, "{mode:?}");
            assert_eq!(read.soup.normals, [Vec3::Z; 3], "{mode:?}");
            assert!(read.position_indices.is_empty(), "{mode:?}");
        }
    }

    // Fails if the materials the `.mtl` loader returns are dropped, or a triangle does not name
    // its `usemtl` material by index.
    #[test]
    fn model_keeps_its_materials() {
        let text = format!("mtllib m.mtl\n{TRIANGLE}usemtl Brick\nf 1/1/1 2/2/1 3/3/1\n");
        let brick = |_: &Path| -> tobj::MTLLoadResult {
            let material = tobj::Material {
                name: "Brick".into(),
                ..Default::default()
            };
            Ok((
                vec![material],
                [("Brick".to_string(), 0)].into_iter().collect(),
            ))
        };
        let read = read_obj(text.as_bytes(), Path::new("m.obj"), ObjMode::Model, brick).unwrap();
        assert_eq!(read.materials.len(), 1);
        assert_eq!(read.materials[0].name, "Brick");
        assert_eq!(read.triangle_materials, [Some(0)]);
    }

    // Fails if an error's line number is not the face's line in the file, counted from 1: the
    // face after QUAD's nine lines is line 10.
    #[test]
    fn errors_give_the_faces_line_counted_from_one() {
        let e = load(&format!("{QUAD}f 1/1/1 2/2/1\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 10: a face needs at least 3 corners, found 2"),
            "{e}"
        );
        let e = load(&format!("{QUAD}f 1/1/1 2/2/1 9/3/1\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(
                "line 10: corner '9/3/1': position index 9 out of range (4 declared so far)"
            ),
            "{e}"
        );
    }

    // Fails if a model whose corners mix `v/vt/vn` and `v/vt` is read (tobj would fill the missing
    // normals with other corners'), or the error miscounts them: one corner with, two without.
    #[test]
    fn model_faces_mixing_normals_are_refused_with_counts() {
        let text = format!("{TRIANGLE}f 1/1/1 2/2 3/3\n");
        let e = read_obj(
            text.as_bytes(),
            Path::new("m.obj"),
            ObjMode::Model,
            no_materials,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains(
                "1 face corners have a normal index and 2 have none: give every corner one \
                 (v/vt/vn) or none (v/vt, and normals are computed)"
            ),
            "{e}"
        );
    }

    // Fails if an `l` line is missed (indented or not) or a line that only starts with the letter
    // l is taken for one, or if dropping them loses anything else: each `l` line is emptied, its
    // line break kept (a `\r` before it goes with the line), and the other lines are unchanged.
    #[test]
    fn polylines_are_found_and_emptied_exactly() {
        assert!(has_polylines("v 0 0 0\n  l 1 2 3\n"));
        assert!(!has_polylines("v 0 0 0\nlod 1\n"));
        assert!(!has_polylines("v 0 0 0\nvt 0 0\n"));
        assert_eq!(
            drop_polylines("v 0 0 0\nl 1 2 3\r\nlod 1\nvt 0 0\n l 1 2"),
            "v 0 0 0\n\nlod 1\nvt 0 0\n"
        );
    }
}
