//! The differential checks that only the tests and the fuzz harness run: the program's OBJ parse
//! against the tutorial's reader (tobj and the checks). Included with `#[path]` by tests/all and
//! fuzz/main.rs, so that the library's API carries none of it.

use std::path::Path;

use glam::{Vec2, Vec3};
use tutorial13::common::objloader::{read_obj, ObjMode, ObjRead};
use tutorial13::pipeline::obj_parse;
use tutorial13::Result;

/// Reads `bytes` in both modes with the program's parse (`pipeline::obj_parse::read_obj_threaded`:
/// one piece per core, and cut into 2 and 5 pieces whatever its size) and with the tutorial's reader,
/// tobj's parse and the checks (`common::objloader::read_obj`), every `mtllib` loaded from
/// `mtl` by tobj, and names the first difference: in the error, the
/// soup (to the bit), the materials, each triangle's material, the `.mtl` files loaded and in what
/// order, and the position indices of a model without normals (each names one position). The
/// tests and the fuzz harness's `obj-tobj` target run it.
pub fn differ_from_tobj(bytes: &[u8], mtl: &[u8]) -> std::result::Result<(), String> {
    use std::cell::RefCell;
    let path = Path::new("differential.obj");
    let cases = [ObjMode::Tutorial, ObjMode::Model]
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
