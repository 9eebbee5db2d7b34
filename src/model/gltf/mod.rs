//! A glTF 2.0 model (`--model FILE.gltf` or `.glb`), read into the same [`Model`] an OBJ gives, so
//! that it goes through the tutorial's pipeline, shaders and debugging aids unchanged.
//!
//! What differs from an OBJ, and why:
//! * **V.** glTF puts the UV origin at the picture's top-left; an OBJ at its bottom-left. V is
//!   turned into the OBJ's (`1 − v`) as it is read, so the maps go up exactly as an OBJ's do and
//!   the bitangent `dP/dV` points up the picture, where a green-up map's green points. Nothing is
//!   negated the tutorial's way (that is for its DDS files, stored upside down).
//! * **Tangents.** A `TANGENT` (xyz, and w: the bitangent is `w × cross(N, T)`) is kept per corner
//!   for the `file` tangent source, the specification's default. Where a primitive has none, the
//!   specification asks for MikkTSpace, which the `file` source then computes over the triangles
//!   of the primitives without (all of them, if none has any).
//! * **Materials.** `baseColorTexture` is the diffuse map, `normalTexture` with its `scale` the
//!   normal map (x and y scaled, as an MTL's `-bm`); specular is the tutorial's constant. The other
//!   metallic-roughness maps have no place in the tutorial's lighting and are left out.
//! * **Bad input** is refused, not patched: a missing buffer or image, an accessor out of its buffer,
//!   a mode other than triangles, no UVs. Without normals, flat ones are computed, as the
//!   specification says a viewer must.
//!
//! This file holds the reading's top-level flow: the document checked, each primitive's corners
//! gathered per material, the notices, the soup assembled and placed. `primitive.rs` reads one
//! primitive, `materials.rs` a material's maps, `uri.rs` what a URI names.

mod materials;
mod primitive;
mod uri;

use std::ops::Range;
use std::path::Path;

use glam::{Mat4, Vec2, Vec3};

use self::materials::uv_set;
use self::primitive::read_primitive;
pub use self::uri::{decode_base64, encode_base64};
use super::parts::Part;
use super::{apply_overrides, group_by_material, placement, MapOverrides, Material, Model, Uvs};
use crate::common::objloader::TriangleSoup;
use crate::tangent_source::FileTangents;
use crate::{Error, Result};

/// The extension that moves and turns UVs per texture; this reader does not apply it.
const TEXTURE_TRANSFORM: &str = "KHR_texture_transform";

/// What a glTF's materials lose here, said once when a glTF model is drawn.
pub const METALLIC_ROUGHNESS: &str = "glTF's metallic-roughness material is not the tutorial's \
    lighting model: baseColorTexture is the diffuse map, normalTexture the normal map, specular is \
    the tutorial's constant 0.3; metallic, roughness, occlusion and emission are left out";

/// Reads a glTF file (JSON or binary) from its bytes; `read_file` reads the buffers and images it
/// names beside it. With `uvs` [`Uvs::Optional`], a primitive without its UV set is read with
/// (0, 0) at every corner.
pub(super) fn load_gltf(
    bytes: &[u8],
    path: &Path,
    overrides: &MapOverrides,
    uvs: Uvs,
    read_file: &dyn Fn(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<Model> {
    let read = Reader {
        path,
        folder: path.parent().unwrap_or(Path::new("")),
        uvs,
        read_file,
    };
    read.model(bytes, overrides).map_err(|reason| Error::Gltf {
        path: path.to_path_buf(),
        reason,
    })
}

/// The file and how to read what it names.
struct Reader<'a> {
    path: &'a Path,
    folder: &'a Path,
    uvs: Uvs,
    read_file: &'a dyn Fn(&Path) -> std::io::Result<Vec<u8>>,
}

/// One material's corners, gathered in the order primitives are met.
#[derive(Default)]
struct Corners {
    vertices: Vec<Vec3>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
    /// The file's tangents, up to the last primitive that has them (zeros for those without).
    tangents: Vec<[f32; 4]>,
    /// Runs of triangles whose primitive has no tangents.
    missing: Vec<Range<usize>>,
}

/// What the primitives gave, gathered per material before the materials are read.
struct Gathered {
    /// Materials in the order primitives first use them; `None` is glTF's default material.
    material_order: Vec<Option<usize>>,
    /// Each material's corners, in the same order.
    corners: Vec<Corners>,
    tangents_missing: bool,
    tangents_supplied: bool,
    normals_missing: bool,
    uvs_filled: bool,
    /// Each primitive's material (an index into `corners`) and triangles, in the order met.
    runs: Vec<(usize, usize)>,
    /// Each mesh instance's part, in the order met.
    parts: Vec<Part>,
}

impl Reader<'_> {
    fn model(&self, bytes: &[u8], overrides: &MapOverrides) -> Result<Model, String> {
        let (document, blob) = read_document(bytes)?;
        let buffers = self.buffers(&document, blob)?;
        let gathered = self.gather(&document, &buffers)?;
        if gathered.corners.iter().all(|c| c.vertices.is_empty()) {
            return Err("no triangles: the scene draws no mesh".into());
        }
        let mut notices = self.notices(&gathered);
        let materials = self.materials(&document, &gathered, &buffers, overrides, &mut notices)?;
        let Gathered {
            corners,
            tangents_supplied,
            normals_missing,
            runs,
            parts,
            ..
        } = gathered;
        let file_order = file_order(&runs, &corners);
        let (soup, triangle_materials, file_tangents) = assemble(corners, tangents_supplied)?;
        // Each material's corners are already together: the grouping keeps them as they are.
        let (mut soup, ranges, _) = group_by_material(soup, &triangle_materials);
        let placement = placement(&soup.vertices).ok_or_else(|| {
            "every triangle is at one point: a model needs some size to be framed and lit"
                .to_string()
        })?;
        for p in &mut soup.vertices {
            *p = placement.to_world(*p);
        }
        Ok(Model {
            path: self.path.to_path_buf(),
            soup,
            materials,
            ranges,
            placement,
            normals_computed: normals_missing,
            file_tangents,
            notices,
            file_order,
            parts,
        })
    }

    /// Reads every primitive of the meshes the scene draws, its corners appended to its
    /// material's.
    fn gather(&self, document: &gltf::Document, buffers: &[Vec<u8>]) -> Result<Gathered, String> {
        let mut material_order: Vec<Option<usize>> = Vec::new();
        let mut corners: Vec<Corners> = Vec::new();
        let (mut tangents_missing, mut tangents_supplied) = (false, false);
        let (mut normals_missing, mut uvs_filled) = (false, false);
        let (mut runs, mut parts) = (Vec::new(), Vec::<Part>::new());
        for (node, mesh, world) in self.mesh_instances(document)? {
            let part_start = runs.iter().map(|&(_, n)| n).sum::<usize>();
            for primitive in mesh.primitives() {
                let at = format!("mesh {} primitive {}", mesh.index(), primitive.index());
                let slot = primitive.material().index();
                let m = match material_order.iter().position(|&s| s == slot) {
                    Some(m) => m,
                    None => {
                        material_order.push(slot);
                        corners.push(Corners::default());
                        material_order.len() - 1
                    }
                };
                let set = uv_set(&primitive.material());
                let has_set = primitive.get(&gltf::Semantic::TexCoords(set)).is_some();
                let set = (has_set || self.uvs == Uvs::Required).then_some(set);
                uvs_filled |= set.is_none();
                let read = read_primitive(&primitive, buffers, world, &at, set)?;
                normals_missing |= read.normals_computed;
                let out = &mut corners[m];
                let (first, count) = (out.vertices.len(), read.vertices.len());
                match read.tangents {
                    Some(t) => {
                        tangents_supplied = true;
                        out.tangents.resize(first, [0.0; 4]);
                        append(&mut out.tangents, t);
                    }
                    None => {
                        tangents_missing = true;
                        out.missing.push(first / 3..(first + count) / 3);
                    }
                }
                append(&mut out.vertices, read.vertices);
                append(&mut out.uvs, read.uvs);
                append(&mut out.normals, read.normals);
                runs.push((m, count / 3));
            }
            // The node's name is the object's in the tool that wrote it (Blender's); its mesh's
            // name is the data's, often shared.
            let name = node.name().or(mesh.name()).unwrap_or_default();
            let end = runs.iter().map(|&(_, n)| n).sum::<usize>();
            parts.push(Part {
                name: name.to_string(),
                triangles: part_start..end,
            });
        }
        Ok(Gathered {
            material_order,
            corners,
            tangents_missing,
            tangents_supplied,
            normals_missing,
            uvs_filled,
            runs,
            parts,
        })
    }

    /// What the primitives lacked and how it was made up for, said once each.
    fn notices(&self, gathered: &Gathered) -> Vec<String> {
        let mut notices = Vec::new();
        if gathered.uvs_filled {
            notices.push(format!(
                "{}: a primitive has no UVs: read with (0, 0) at every corner (its UVs are not \
                 used here)",
                self.path.display()
            ));
        }
        if gathered.normals_missing {
            notices.push(format!(
                "{}: a primitive has no NORMAL: flat normals computed, as the specification says",
                self.path.display()
            ));
        }
        if gathered.tangents_missing && gathered.tangents_supplied {
            notices.push(format!(
                "{}: some primitives have no TANGENT: MikkTSpace is computed for those, the others \
                 keep the file's",
                self.path.display()
            ));
        }
        notices
    }

    /// The materials in the order primitives first use them, with the command line's overrides.
    fn materials(
        &self,
        document: &gltf::Document,
        gathered: &Gathered,
        buffers: &[Vec<u8>],
        overrides: &MapOverrides,
        notices: &mut Vec<String>,
    ) -> Result<Vec<Material>, String> {
        let mut materials = Vec::with_capacity(gathered.material_order.len());
        for slot in &gathered.material_order {
            let material = match slot {
                Some(i) => document.materials().nth(*i),
                None => None,
            };
            materials.push(self.material(material, buffers, notices)?);
        }
        for material in &mut materials {
            apply_overrides(material, overrides);
        }
        Ok(materials)
    }

    /// The meshes the scene draws, each with its node and the node's world transform: the default
    /// scene (or the first), else every node that is no node's child.
    fn mesh_instances<'d>(
        &self,
        document: &'d gltf::Document,
    ) -> Result<Vec<(gltf::Node<'d>, gltf::Mesh<'d>, Mat4)>, String> {
        let roots: Vec<gltf::Node> = match document.default_scene().or(document.scenes().next()) {
            Some(scene) => scene.nodes().collect(),
            None => {
                let mut child = vec![false; document.nodes().len()];
                for node in document.nodes() {
                    for c in node.children() {
                        child[c.index()] = true;
                    }
                }
                document.nodes().filter(|n| !child[n.index()]).collect()
            }
        };
        let mut seen = vec![false; document.nodes().len()];
        let mut stack: Vec<(gltf::Node, Mat4)> =
            roots.into_iter().map(|n| (n, Mat4::IDENTITY)).collect();
        let mut out = Vec::new();
        while let Some((node, parent)) = stack.pop() {
            // Nodes form trees: a node reached twice is a cycle, or a child of two parents.
            if std::mem::replace(&mut seen[node.index()], true) {
                return Err(format!(
                    "node {} is reached twice: not a tree",
                    node.index()
                ));
            }
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            if let Some(mesh) = node.mesh() {
                out.push((node.clone(), mesh, world));
            }
            stack.extend(node.children().map(|c| (c, world)));
        }
        // In file order, whatever order the stack met them in.
        out.reverse();
        Ok(out)
    }
}

/// The file parsed and checked: what the `gltf` crate assumes (see [`check_before_validation`]),
/// then its validation, then no UVs moved per texture. Returns the document and the GLB's binary
/// chunk.
fn read_document(bytes: &[u8]) -> Result<(gltf::Document, Option<Vec<u8>>), String> {
    let not_read = |e: gltf::Error| match bytes.starts_with(b"glTF") {
        true => format!("not a binary glTF this program reads: {e}"),
        false => format!("not glTF JSON this program reads: {e}"),
    };
    // The crate subtracts the header's size from the length the header states unchecked.
    if bytes.starts_with(b"glTF") && bytes.len() >= 12 {
        let length = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
        if length < 12 {
            return Err(format!(
                "not a binary glTF this program reads: its header gives a length of \
                 {length} bytes, less than the header's own 12"
            ));
        }
    }
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(not_read)?;
    // The crate's validation and accessors assume these (they panic where they do not hold).
    let root = document.into_json();
    check_before_validation(&root)?;
    let document = gltf::Document::from_json(root).map_err(not_read)?;
    if document.extensions_used().any(|e| e == TEXTURE_TRANSFORM) {
        return Err(format!(
            "uses {TEXTURE_TRANSFORM} (UVs moved per texture), which this program does not \
             apply: its maps would be misplaced"
        ));
    }
    Ok((document, blob))
}

/// Each soup triangle's index in the order the primitives were met ([`Model::file_order`]): the
/// soup holds each material's corners (`corners`) one after the other, each material's in the order
/// met; `runs` are the primitives' materials and triangles. Empty where the two orders are one.
fn file_order(runs: &[(usize, usize)], corners: &[Corners]) -> Vec<u32> {
    let mut next: Vec<usize> = corners
        .iter()
        .scan(0, |start, c| {
            let first = *start;
            *start += c.vertices.len() / 3;
            Some(first)
        })
        .collect();
    let mut order = Vec::new();
    let mut file = 0;
    for &(m, triangles) in runs {
        for _ in 0..triangles {
            order.push((next[m], file as u32));
            next[m] += 1;
            file += 1;
        }
    }
    if order.iter().all(|&(soup, file)| soup == file as usize) {
        return Vec::new();
    }
    let mut file_order = vec![0u32; order.len()];
    for (soup, file) in order {
        file_order[soup] = file;
    }
    file_order
}

/// The materials' corners one after the other, as one soup, with each triangle's material and
/// the file's tangents (if any primitive has them); refused if a value is not finite.
fn assemble(
    corners: Vec<Corners>,
    tangents_supplied: bool,
) -> Result<(TriangleSoup, Vec<usize>, Option<FileTangents>), String> {
    let mut soup = TriangleSoup::default();
    let mut tangents = Vec::new();
    let mut missing: Vec<Range<usize>> = Vec::new();
    let mut triangle_materials = Vec::new();
    for (m, mut c) in corners.into_iter().enumerate() {
        let first = soup.vertices.len() / 3;
        triangle_materials.extend(std::iter::repeat_n(m, c.vertices.len() / 3));
        for r in c.missing {
            let r = first + r.start..first + r.end;
            match missing.last_mut() {
                Some(last) if last.end == r.start => last.end = r.end,
                _ => missing.push(r),
            }
        }
        if tangents_supplied {
            c.tangents.resize(c.vertices.len(), [0.0; 4]);
            append(&mut tangents, c.tangents);
        }
        append(&mut soup.vertices, c.vertices);
        append(&mut soup.uvs, c.uvs);
        append(&mut soup.normals, c.normals);
    }
    let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
    let all_finite = soup.vertices.iter().all(|p| finite(&p.to_array()))
        && soup.uvs.iter().all(|uv| finite(&uv.to_array()))
        && soup.normals.iter().all(|n| finite(&n.to_array()))
        && tangents.iter().all(|t| finite(t));
    if !all_finite {
        return Err(
            "a position, UV, normal or tangent is not a finite number (as stored, or \
             after its node's transform)"
                .into(),
        );
    }
    let file_tangents = tangents_supplied.then_some(FileTangents {
        per_corner: tangents,
        missing,
    });
    Ok((soup, triangle_materials, file_tangents))
}

/// What the `gltf` crate's validation and accessors take for granted without checking: a
/// primitive's POSITION accessor exists (its validation reads its bounds first), and an image has a
/// URI or a buffer view with its MIME type.
fn check_before_validation(root: &gltf::json::Root) -> Result<(), String> {
    let positions = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive.attributes.get(&positions) {
                if index.value() >= root.accessors.len() {
                    return Err(format!(
                        "mesh {m} primitive {p}: POSITION names accessor {}, of {}",
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    for (i, image) in root.images.iter().enumerate() {
        let source = (&image.uri, &image.buffer_view, &image.mime_type);
        if !matches!(source, (Some(_), None, _) | (None, Some(_), Some(_))) {
            return Err(format!(
                "image {i}: neither a URI nor a buffer view with its mimeType"
            ));
        }
    }
    Ok(())
}

/// `more` at the end of `to`; taken whole when `to` is empty (a file of one primitive and one
/// material, the usual case), as copying a million triangles' corners twice cost tens of ms.
fn append<T>(to: &mut Vec<T>, mut more: Vec<T>) {
    if to.is_empty() {
        *to = more;
    } else {
        to.append(&mut more);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a triangle of primitives whose materials interleave is not given its index in the
    // order the primitives were met, or if an order that is the soup's is not left empty.
    #[test]
    fn the_file_order_follows_the_primitives_met() {
        let corners = |triangles: usize| Corners {
            vertices: vec![Vec3::ZERO; 3 * triangles],
            ..Corners::default()
        };
        // Material 0's primitives hold the file's triangles 0, 1 and 3; material 1's 2, 4 and 5.
        let runs = [(0, 2), (1, 1), (0, 1), (1, 2)];
        assert_eq!(
            file_order(&runs, &[corners(3), corners(3)]),
            [0, 1, 3, 2, 4, 5]
        );
        assert!(file_order(&[(0, 2), (0, 1), (1, 3)], &[corners(3), corners(3)]).is_empty());
    }

    // Fails if a node's transform is not applied (the fuzz corpus's quad sits under a node that
    // moves it by +2 in x and a child that mirrors x), if the mirror leaves the winding clockwise
    // (the quad would face away from its normal), or if the file's tangent keeps its w there.
    #[test]
    fn node_transforms_move_mirror_and_keep_the_winding() {
        let bytes = include_bytes!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/fuzz/corpus/gltf/mirrored-tangents.gltf"
        ));
        let none = |_: &Path| Err(std::io::ErrorKind::NotFound.into());
        let path = Path::new("quad.gltf");
        let model =
            super::super::load_model_bytes(bytes, path, &MapOverrides::default(), none).unwrap();
        // The file's quad spans x 0..1; mirrored and moved it spans 1..2.
        assert_eq!(model.placement.center, Vec3::new(1.5, 0.5, 0.0));
        for t in model.soup.vertices.chunks(3) {
            let face = (t[1] - t[0]).cross(t[2] - t[0]);
            assert!(face.z > 0.0, "a triangle faces {face}");
        }
        assert!(model.soup.normals.iter().all(|&n| n == Vec3::Z));
        let tangents = model.file_tangents.unwrap();
        assert!(tangents.missing.is_empty());
        assert!(
            tangents
                .per_corner
                .iter()
                .all(|&t| t == [-1.0, 0.0, 0.0, 1.0]),
            "{tangents:?}"
        );
    }
}
