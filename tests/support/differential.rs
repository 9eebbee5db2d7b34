//! The differential checks that only the tests and the fuzz harness run: the program's OBJ parse
//! against the tutorial's reader (tobj and the checks). Included with `#[path]` by tests/all and
//! fuzz/main.rs, so that the library's API carries none of it.

use std::path::Path;

use glam::{Vec2, Vec3};
use tutorial13::common::objloader::{read_obj, ObjMode, ObjRead};
use tutorial13::pipeline::obj_parse;
use tutorial13::Result;

/// Reads `bytes` in the three modes (tutorial, model, shape) with the program's parse (`pipeline::obj_parse::read_obj_threaded`:
/// one piece per core, and cut into 2 and 5 pieces whatever its size) and with the tutorial's reader,
/// tobj's parse and the checks (`common::objloader::read_obj`), every `mtllib` loaded from
/// `mtl` by tobj, and names the first difference: in the error, the
/// soup (to the bit), the materials, each triangle's material, the `.mtl` files loaded and in what
/// order, and the position indices of a model without normals (each names one position). The
/// tests and the fuzz harness's `obj-tobj` target run it.
pub fn differ_from_tobj(bytes: &[u8], mtl: &[u8]) -> std::result::Result<(), String> {
    use std::cell::RefCell;
    let path = Path::new("differential.obj");
    let cases = [ObjMode::Tutorial, ObjMode::Model, ObjMode::Shape]
        .into_iter()
        .flat_map(|mode| [None, Some(2), Some(5)].map(|pieces| (mode, pieces)));
    for (mode, pieces) in cases {
        let mode_name = format!("{mode:?} mode, {pieces:?} pieces");
        let calls = [RefCell::new(Vec::new()), RefCell::new(Vec::new())];
        let loader = |k: usize| {
            let calls = &calls[k];
            move |name: &Path| {
                calls.borrow_mut().push(name.to_path_buf());
                tobj::load_mtl_buf(&mut &mtl[..])
            }
        };
        let own = obj_parse::read_obj_threaded(bytes, path, mode, loader(0), pieces);
        let reference = read_obj(bytes, path, mode, loader(1));
        let (own, reference) = match (own, reference) {
            (Err(a), Err(b)) if a.to_string() == b.to_string() => continue,
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => {
                let show = |r: &Result<ObjRead>| match r {
                    Ok(read) => format!("{} triangles", read.soup.triangle_count()),
                    Err(e) => e.to_string(),
                };
                return Err(format!(
                    "{mode_name}: read {} but tobj {}",
                    show(&a),
                    show(&b)
                ));
            }
        };
        let bits3 = |v: &[Vec3]| -> Vec<[u32; 3]> {
            v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
        };
        let bits2 = |v: &[Vec2]| -> Vec<[u32; 2]> {
            v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
        };
        let names = |read: &ObjRead| -> Vec<String> {
            read.materials.iter().map(|m| m.name.clone()).collect()
        };
        let differences = [
            (
                "positions",
                bits3(&own.soup.vertices) != bits3(&reference.soup.vertices),
            ),
            ("UVs", bits2(&own.soup.uvs) != bits2(&reference.soup.uvs)),
            (
                "normals",
                bits3(&own.soup.normals) != bits3(&reference.soup.normals),
            ),
            ("materials", names(&own) != names(&reference)),
            (
                "triangle materials",
                own.triangle_materials != reference.triangle_materials,
            ),
            (
                "missing normals",
                own.normals_missing != reference.normals_missing,
            ),
            ("mtl loads", *calls[0].borrow() != *calls[1].borrow()),
            ("missing UVs", own.uvs_missing != reference.uvs_missing),
            (
                "position indices",
                own.position_indices.len() != reference.position_indices.len(),
            ),
        ];
        if let Some((what, _)) = differences.iter().find(|(_, differ)| *differ) {
            return Err(format!("{mode_name}: the {what} differ from tobj's"));
        }
        // tobj numbers positions per object, this reader in the whole file: compare what they name.
        let mut named = std::collections::HashMap::new();
        for (&index, p) in own.position_indices.iter().zip(&own.soup.vertices) {
            if *named.entry(index).or_insert(p.to_array().map(f32::to_bits))
                != p.to_array().map(f32::to_bits)
            {
                return Err(format!(
                    "{mode_name}: position index {index} names two positions"
                ));
            }
        }
    }
    Ok(())
}

/// How a shape without UVs was read before [`ObjMode::Shape`] read it in one pass, kept as that
/// reader's reference: `text` with a `vt 0 0` first and every face corner pointing at it (`v` →
/// `v/1`, `v//n` → `v/1/n`), if it has faces and none of them names a UV; else `None`. Read as a
/// model, it gives the soup the shape's one pass must give.
pub fn with_one_uv(text: &str) -> Option<String> {
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    out.push_str("vt 0 0\n");
    let mut faces = 0;
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.first() != Some(&"f") {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        faces += 1;
        out.push('f');
        for corner in &words[1..] {
            let mut parts = corner.splitn(3, '/');
            let (v, vt, vn) = (parts.next()?, parts.next(), parts.next());
            if vt.is_some_and(|vt| !vt.is_empty()) {
                return None;
            }
            out.push(' ');
            out.push_str(v);
            out.push_str("/1");
            if let Some(vn) = vn {
                out.push('/');
                out.push_str(vn);
            }
        }
        out.push('\n');
    }
    (faces > 0).then_some(out)
}

/// Reads `bytes` (an OBJ) as a bake's HIGH (`model::load_shape_bytes`: one pass) and as it was read
/// before the one pass (`with_one_uv`'s text read as a model, with the notice that said so; a file
/// that names a UV read as it is), and names the first difference: one read refused and not the
/// other, other errors where no rewrite was made (a rewrite's line numbers were one past the
/// file's), or, read both ways, the soup (to the bit), materials, ranges, placement, notices or
/// file order. Gives the one pass's read. The tests and the fuzz harness's `model` target run it.
pub fn shape_differs_from_rewrite(
    bytes: &[u8],
    path: &Path,
    read_file: impl Fn(&Path) -> std::io::Result<Vec<u8>> + Copy,
) -> std::result::Result<Result<tutorial13::model::Model>, String> {
    use tutorial13::model::{load_model_bytes, load_shape_bytes, MapOverrides};
    let shape = load_shape_bytes(bytes, path, read_file);
    let rewritten = std::str::from_utf8(bytes).ok().and_then(with_one_uv);
    let overrides = MapOverrides::default();
    let before = match &rewritten {
        Some(text) => {
            load_model_bytes(text.as_bytes(), path, &overrides, read_file).map(|mut m| {
                m.notices.push(format!(
                    "{}: no UVs: read with (0, 0) at every corner (its UVs are not used here)",
                    path.display()
                ));
                m
            })
        }
        None => load_model_bytes(bytes, path, &overrides, read_file),
    };
    let (one_pass, before) = match (&shape, before) {
        (Err(a), Err(b)) if rewritten.is_some() || a.to_string() == b.to_string() => {
            return Ok(shape)
        }
        (Ok(a), Ok(b)) => (a, b),
        (a, b) => {
            let show = |r: std::result::Result<&tutorial13::model::Model, String>| match r {
                Ok(m) => format!("{} triangles", m.soup.triangle_count()),
                Err(e) => e,
            };
            return Err(format!(
                "the shape's one pass read {} but the rewrite {}",
                show(a.as_ref().map_err(|e| e.to_string())),
                show(b.as_ref().map_err(|e| e.to_string()))
            ));
        }
    };
    let bits = |m: &tutorial13::model::Model| -> Vec<u32> {
        let soup = &m.soup;
        let points = soup.vertices.iter().chain(&soup.normals);
        let uvs = soup.uvs.iter().flat_map(|p| p.to_array());
        points
            .flat_map(|p| p.to_array())
            .chain(uvs)
            .map(f32::to_bits)
            .collect()
    };
    let words = |m: &tutorial13::model::Model| {
        format!(
            "{:?} {:?} {:?} {} {:?} {:?} {}",
            m.materials,
            m.ranges,
            m.placement,
            m.normals_computed,
            m.notices,
            m.file_order,
            m.file_tangents.is_some()
        )
    };
    if bits(one_pass) != bits(&before) {
        return Err("the shape's one pass read another soup than the rewrite".into());
    }
    if words(one_pass) != words(&before) {
        return Err(format!(
            "the shape's one pass read {} but the rewrite {}",
            words(one_pass),
            words(&before)
        ));
    }
    Ok(shape)
}
