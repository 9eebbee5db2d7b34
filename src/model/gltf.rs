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

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::{
    apply_overrides, group_by_material, placement, MapOverrides, MapSource, Material, Model, Uvs,
};
use crate::common::objloader::TriangleSoup;
use crate::tangents::FileTangents;
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
    missing: Vec<std::ops::Range<usize>>,
}

impl Reader<'_> {
    fn model(&self, bytes: &[u8], overrides: &MapOverrides) -> Result<Model, String> {
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
        let buffers = self.buffers(&document, blob)?;
        let mut notices = Vec::new();

        // Materials in the order primitives first use them; `None` is glTF's default material.
        let mut material_order: Vec<Option<usize>> = Vec::new();
        let mut corners: Vec<Corners> = Vec::new();
        let (mut tangents_missing, mut tangents_supplied) = (false, false);
        let (mut normals_missing, mut uvs_filled) = (false, false);
        for (mesh, world) in self.mesh_instances(&document)? {
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
                let read = read_primitive(&primitive, &buffers, world, &at, set)?;
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
            }
        }
        if corners.iter().all(|c| c.vertices.is_empty()) {
            return Err("no triangles: the scene draws no mesh".into());
        }
        if uvs_filled {
            notices.push(format!(
                "{}: a primitive has no UVs: read with (0, 0) at every corner (its UVs are not \
                 used here)",
                self.path.display()
            ));
        }
        if normals_missing {
            notices.push(format!(
                "{}: a primitive has no NORMAL: flat normals computed, as the specification says",
                self.path.display()
            ));
        }
        if tangents_missing && tangents_supplied {
            notices.push(format!(
                "{}: some primitives have no TANGENT: MikkTSpace is computed for those, the others \
                 keep the file's",
                self.path.display()
            ));
        }

        let mut materials = Vec::with_capacity(material_order.len());
        for slot in &material_order {
            let material = match slot {
                Some(i) => document.materials().nth(*i),
                None => None,
            };
            materials.push(self.material(material, &buffers, &mut notices)?);
        }
        for material in &mut materials {
            apply_overrides(material, overrides);
        }

        let mut soup = TriangleSoup::default();
        let mut tangents = Vec::new();
        let mut missing: Vec<std::ops::Range<usize>> = Vec::new();
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
        // Each material's corners are already together: the grouping keeps them as they are.
        let (mut soup, ranges) = group_by_material(soup, &triangle_materials);
        let placement = placement(&soup.vertices).ok_or_else(|| {
            "every triangle is at one point: a model needs some size to be framed and lit"
                .to_string()
        })?;
        for p in &mut soup.vertices {
            *p = placement.to_world(*p);
        }
        let file_tangents = tangents_supplied.then_some(FileTangents {
            per_corner: tangents,
            missing,
        });
        Ok(Model {
            path: self.path.to_path_buf(),
            soup,
            materials,
            ranges,
            placement,
            normals_computed: normals_missing,
            file_tangents,
            notices,
        })
    }

    /// Every buffer's bytes: the GLB's BIN chunk, a data URI, or a file beside the model.
    fn buffers(
        &self,
        document: &gltf::Document,
        mut blob: Option<Vec<u8>>,
    ) -> Result<Vec<Vec<u8>>, String> {
        let mut out = Vec::new();
        for buffer in document.buffers() {
            let what = format!("buffer {}", buffer.index());
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => blob
                    .take()
                    .ok_or_else(|| format!("{what}: the file has no binary chunk"))?,
                gltf::buffer::Source::Uri(uri) => self.uri(uri, &what)?,
            };
            if data.len() < buffer.length() {
                return Err(format!(
                    "{what}: {} bytes where the file says {}: cut short",
                    data.len(),
                    buffer.length()
                ));
            }
            out.push(data);
        }
        Ok(out)
    }

    /// A buffer's or an image's URI: a `data:` URI decoded, or a file beside the model.
    fn uri(&self, uri: &str, what: &str) -> Result<Vec<u8>, String> {
        if let Some(data) = uri.strip_prefix("data:") {
            let (header, payload) = data
                .split_once(',')
                .ok_or_else(|| format!("{what}: a data URI without a comma"))?;
            if !header.ends_with(";base64") {
                return Err(format!("{what}: a data URI that is not base64"));
            }
            return decode_base64(payload).ok_or_else(|| format!("{what}: malformed base64"));
        }
        let name = percent_decode(uri)
            .ok_or_else(|| format!("{what}: malformed URI '{}'", one_line(uri)))?;
        let file = self.folder.join(&name);
        (self.read_file)(&file)
            .map_err(|e| format!("{what}: {}: {e}", one_line(&file.display().to_string())))
    }

    /// The meshes the scene draws, each with its node's world transform: the default scene (or
    /// the first), else every node that is no node's child.
    fn mesh_instances<'d>(
        &self,
        document: &'d gltf::Document,
    ) -> Result<Vec<(gltf::Mesh<'d>, Mat4)>, String> {
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
                out.push((mesh, world));
            }
            stack.extend(node.children().map(|c| (c, world)));
        }
        // In file order, whatever order the stack met them in.
        out.reverse();
        Ok(out)
    }

    /// A glTF material's maps (`None`: the default material, white and flat).
    fn material(
        &self,
        material: Option<gltf::Material>,
        buffers: &[Vec<u8>],
        notices: &mut Vec<String>,
    ) -> Result<Material, String> {
        let Some(material) = material else {
            return Ok(Material {
                name: "(default)".into(),
                diffuse: MapSource::Neutral,
                normal: MapSource::Neutral,
                specular: MapSource::Neutral,
            });
        };
        let name = material.name().map_or_else(
            || format!("material {}", material.index().unwrap_or(0)),
            str::to_string,
        );
        self.check_tex_coord(&material, &name, notices);
        let pbr = material.pbr_metallic_roughness();
        let diffuse = match pbr.base_color_texture() {
            Some(info) => {
                let named_by = format!("baseColorTexture of '{name}'");
                self.check_sampler(&info.texture(), &named_by, notices);
                self.image(info.texture(), buffers, named_by, None)?
            }
            None => {
                let [r, g, b, _] = pbr.base_color_factor();
                MapSource::Colour([r, g, b])
            }
        };
        let normal = match material.normal_texture() {
            Some(info) => {
                let named_by = format!("normalTexture of '{name}'");
                let scale = Some(info.scale()).filter(|&s| s != 1.0);
                self.check_sampler(&info.texture(), &named_by, notices);
                self.image(info.texture(), buffers, named_by, scale)?
            }
            None => MapSource::Neutral,
        };
        Ok(Material {
            name,
            diffuse,
            normal,
            specular: MapSource::Neutral,
        })
    }

    /// Says when a material's two maps name different UV sets: the tutorial's shaders have one.
    fn check_tex_coord(&self, material: &gltf::Material, name: &str, notices: &mut Vec<String>) {
        if let (Some(d), Some(n)) = map_uv_sets(material) {
            if d != n {
                notices.push(format!(
                    "{}: '{name}': baseColorTexture uses TEXCOORD_{d}, normalTexture \
                     TEXCOORD_{n}: both are read with TEXCOORD_{n}, the normal map's (the \
                     tutorial's shaders have one UV set)",
                    self.path.display()
                ));
            }
        }
    }

    /// Says when a texture's sampler asks for wrapping other than glTF's default, REPEAT: every
    /// map is sampled the tutorial's way (REPEAT, trilinear), which differs only where UVs leave
    /// 0..1. Filters are not said: they change no texel's place.
    fn check_sampler(&self, texture: &gltf::Texture, named_by: &str, notices: &mut Vec<String>) {
        use gltf::texture::WrappingMode;
        let sampler = texture.sampler();
        let asked: Vec<String> = [("S", sampler.wrap_s()), ("T", sampler.wrap_t())]
            .into_iter()
            .filter(|(_, mode)| *mode != WrappingMode::Repeat)
            .map(|(axis, mode)| format!("{mode:?} on {axis}"))
            .collect();
        if !asked.is_empty() {
            notices.push(format!(
                "{}: {named_by}'s sampler asks for {}: sampled with Repeat, the tutorial's \
                 wrapping, which differs only where its UVs leave 0..1",
                self.path.display(),
                asked.join(" and ")
            ));
        }
    }

    /// A texture's picture, read now (decoded when the maps are uploaded).
    fn image(
        &self,
        texture: gltf::Texture,
        buffers: &[Vec<u8>],
        named_by: String,
        bump_multiplier: Option<f32>,
    ) -> Result<MapSource, String> {
        let image = texture.source();
        let what = format!("image {}", image.index());
        let (bytes, name) = match image.source() {
            gltf::image::Source::View { view, .. } => {
                (view_bytes(&view, buffers, &what)?.to_vec(), None)
            }
            gltf::image::Source::Uri { uri, .. } => {
                let name = (!uri.starts_with("data:")).then(|| uri.to_string());
                (self.uri(uri, &what)?, name)
            }
        };
        let mut path = self.path.as_os_str().to_owned();
        match name {
            Some(name) => path = self.folder.join(name).into_os_string(),
            None => path.push(format!(" ({what})")),
        }
        Ok(MapSource::Bytes {
            bytes: Arc::from(bytes),
            path: PathBuf::from(path),
            named_by: format!("{named_by} in {}", self.path.display()),
            bump_multiplier,
        })
    }
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

/// One primitive's corners, transformed to the scene's space.
struct Primitive {
    vertices: Vec<Vec3>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
    tangents: Option<Vec<[f32; 4]>>,
    normals_computed: bool,
}

/// The UV set a material's maps are laid with: its normal map's (the tangent frame follows it),
/// else its diffuse map's, else TEXCOORD_0 (glTF's default material has no map).
fn uv_set(material: &gltf::Material) -> u32 {
    let (diffuse, normal) = map_uv_sets(material);
    normal.or(diffuse).unwrap_or(0)
}

/// The UV sets a material's diffuse (`baseColorTexture`) and normal maps name, where it has them.
fn map_uv_sets(material: &gltf::Material) -> (Option<u32>, Option<u32>) {
    let pbr = material.pbr_metallic_roughness();
    (
        pbr.base_color_texture().map(|info| info.tex_coord()),
        material.normal_texture().map(|info| info.tex_coord()),
    )
}

/// A primitive's corners, in `world`, with UV set `set` (`TEXCOORD_set`); with `None`, every
/// corner's UV is (0, 0).
fn read_primitive(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    world: Mat4,
    at: &str,
    set: Option<u32>,
) -> Result<Primitive, String> {
    if primitive.mode() != Mode::Triangles {
        return Err(format!(
            "{at}: mode {:?}: only triangles are drawn",
            primitive.mode()
        ));
    }
    let float = &[DataType::F32][..];
    let unorm = &[DataType::F32, DataType::U8, DataType::U16][..];
    let semantic = gltf::Semantic::Positions;
    let positions = primitive
        .get(&semantic)
        .ok_or_else(|| format!("{at}: no POSITION"))?;
    let count = check_accessor(&positions, "POSITION", Dimensions::Vec3, float, buffers, at)?;
    let mut checked = Vec::new();
    let uv_name = format!("TEXCOORD_{}", set.unwrap_or(0));
    if let Some(set) = set {
        let uvs = primitive
            .get(&gltf::Semantic::TexCoords(set))
            .ok_or_else(|| match set {
                0 => {
                    format!("{at}: no TEXCOORD_0: a normal map needs UVs to be laid on the surface")
                }
                _ => format!("{at}: no TEXCOORD_{set}, the UV set its material's maps name"),
            })?;
        checked.push((uvs, uv_name.as_str(), Dimensions::Vec2, unorm));
    }
    let normals = primitive.get(&gltf::Semantic::Normals);
    if let Some(n) = &normals {
        checked.push((n.clone(), "NORMAL", Dimensions::Vec3, float));
    }
    // Without normals a file's tangents are ignored, as the specification says.
    let tangents = primitive
        .get(&gltf::Semantic::Tangents)
        .filter(|_| normals.is_some());
    if let Some(t) = &tangents {
        checked.push((t.clone(), "TANGENT", Dimensions::Vec4, float));
    }
    for (accessor, name, dimensions, types) in checked {
        let n = check_accessor(&accessor, name, dimensions, types, buffers, at)?;
        if n != count {
            return Err(format!(
                "{at}: {name} has {n} elements where POSITION has {count}"
            ));
        }
    }
    let clock = crate::clock::Instant::now();
    let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let out_of_range = || format!("{at}: an accessor is out of its buffer");
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or_else(out_of_range)?
        .map(|p| world.transform_point3(Vec3::from(p)))
        .collect();
    let uvs: Vec<Vec2> = match set {
        Some(set) => reader
            .read_tex_coords(set)
            .ok_or_else(out_of_range)?
            .into_f32()
            .map(|[u, v]| Vec2::new(u, 1.0 - v))
            .collect(),
        None => vec![Vec2::ZERO; count],
    };
    let file_normals: Option<Vec<Vec3>> = match normals {
        Some(_) => Some(
            reader
                .read_normals()
                .ok_or_else(out_of_range)?
                .map(Vec3::from)
                .collect(),
        ),
        None => None,
    };
    // Directions go across by the transform, normals by its inverse transpose: both once a primitive.
    let m = Mat3::from_mat4(world);
    let normal_matrix = m.inverse().transpose();
    let tangents: Option<Vec<Vec4>> = match (&tangents, &file_normals) {
        (Some(_), Some(normals)) => Some(
            reader
                .read_tangents()
                .ok_or_else(out_of_range)?
                .zip(normals)
                .map(|(t, &n)| file_tangent(m, normal_matrix, Vec4::from(t), n))
                .collect(),
        ),
        _ => None,
    };
    let normals: Option<Vec<Vec3>> = file_normals.map(|n| {
        n.into_iter()
            .map(|n| (normal_matrix * n).normalize_or(Vec3::Z))
            .collect()
    });

    let indices: Vec<u32> = match primitive.indices() {
        Some(accessor) => {
            let types = [DataType::U8, DataType::U16, DataType::U32];
            check_accessor(
                &accessor,
                "indices",
                Dimensions::Scalar,
                &types,
                buffers,
                at,
            )?;
            let read = reader.read_indices().ok_or_else(out_of_range)?;
            read.into_u32().collect()
        }
        None => (0..count as u32).collect(),
    };
    if indices.len() % 3 != 0 {
        return Err(format!(
            "{at}: {} indices, not a whole number of triangles",
            indices.len()
        ));
    }
    if let Some(&i) = indices.iter().find(|&&i| i as usize >= count) {
        return Err(format!(
            "{at}: index {i} past the {count} vertices of its accessors"
        ));
    }
    log::trace!(
        "{at}: accessors read in {:.1} ms",
        clock.elapsed().as_secs_f64() * 1e3
    );
    let clock = crate::clock::Instant::now();
    // A mirroring transform turns the winding round: corners 1 and 2 swapped keep it
    // counter-clockwise, as the specification says.
    let mirrored = world.determinant() < 0.0;
    let corner_order = |t: &[u32]| -> [usize; 3] {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        if mirrored {
            [a, c, b]
        } else {
            [a, b, c]
        }
    };
    let corners = indices.chunks_exact(3).flat_map(corner_order);
    let corners: Vec<usize> = corners.collect();
    let vertices: Vec<Vec3> = corners.iter().map(|&i| positions[i]).collect();
    let normals_computed = normals.is_none();
    let normals = match &normals {
        Some(n) => corners.iter().map(|&i| n[i]).collect(),
        None => flat_normals(&vertices),
    };
    let primitive = Primitive {
        uvs: corners.iter().map(|&i| uvs[i]).collect(),
        normals,
        tangents: tangents.map(|t| corners.iter().map(|&i| t[i].to_array()).collect()),
        vertices,
        normals_computed,
    };
    log::trace!(
        "{at}: corners expanded in {:.1} ms",
        clock.elapsed().as_secs_f64() * 1e3
    );
    Ok(primitive)
}

/// `text` with its control characters (a line break in a file's URI) escaped, so that an error
/// naming it stays one line.
fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| match c.is_control() {
            true => c.escape_default().to_string(),
            false => c.to_string(),
        })
        .collect()
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

/// A file's tangent taken to the scene's space: xyz by the transform, w chosen again so that
/// `w × cross(N, T)` is still the transformed bitangent (a mirroring transform flips it).
/// `normal` is the corner's normal in the file's space; `m` the transform's 3×3 part and
/// `normal_matrix` its inverse transpose.
fn file_tangent(m: Mat3, normal_matrix: Mat3, tangent: Vec4, normal: Vec3) -> Vec4 {
    let w = if tangent.w < 0.0 { -1.0 } else { 1.0 };
    let t = tangent.truncate();
    let t_world = (m * t).normalize_or(Vec3::X);
    let b_world = m * (w * normal.cross(t));
    let n_world = normal_matrix * normal;
    let sign = match n_world.cross(t_world).dot(b_world) < 0.0 {
        true => -1.0,
        false => 1.0,
    };
    t_world.extend(sign)
}

/// One face normal per corner (a degenerate triangle gets +z).
fn flat_normals(vertices: &[Vec3]) -> Vec<Vec3> {
    vertices
        .chunks_exact(3)
        .flat_map(|t| {
            let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or(Vec3::Z);
            [n; 3]
        })
        .collect()
}

/// Checks what the crate's reader takes for granted (the element type, a buffer view, its range
/// inside the buffer) and returns the accessor's count.
fn check_accessor(
    accessor: &gltf::Accessor,
    name: &str,
    dimensions: Dimensions,
    types: &[DataType],
    buffers: &[Vec<u8>],
    at: &str,
) -> Result<usize, String> {
    let what = format!("{at}: {name} (accessor {})", accessor.index());
    if accessor.sparse().is_some() {
        return Err(format!("{what}: sparse, which this program does not read"));
    }
    if accessor.dimensions() != dimensions || !types.contains(&accessor.data_type()) {
        return Err(format!(
            "{what}: {:?} of {:?}, where {dimensions:?} of {types:?} is read",
            accessor.dimensions(),
            accessor.data_type()
        ));
    }
    let view = accessor
        .view()
        .ok_or_else(|| format!("{what}: no buffer view"))?;
    let count = accessor.count();
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    let end = count
        .checked_sub(1)
        .and_then(|last| stride.checked_mul(last))
        .and_then(|s| s.checked_add(size))
        .and_then(|s| s.checked_add(accessor.offset()));
    let fits = view_bytes(&view, buffers, &what).is_ok_and(|b| end.is_some_and(|e| e <= b.len()));
    if count == 0 || stride < size || !fits {
        return Err(format!(
            "{what}: out of range ({count} elements of {size} bytes, stride {stride}, from byte {} \
             of a view of {} bytes)",
            accessor.offset(),
            view.length()
        ));
    }
    Ok(count)
}

/// A buffer view's bytes, if the view lies inside its buffer.
fn view_bytes<'b>(
    view: &gltf::buffer::View,
    buffers: &'b [Vec<u8>],
    what: &str,
) -> Result<&'b [u8], String> {
    let buffer = buffers.get(view.buffer().index());
    let range = view.offset()..view.offset().saturating_add(view.length());
    buffer
        .and_then(|b| b.get(range))
        .ok_or_else(|| format!("{what}: buffer view {} out of its buffer", view.index()))
}

/// A URI's `%XX` escapes decoded (a file name with spaces is written `%20`).
fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Standard base64 (RFC 4648, with or without padding), as data URIs carry it.
pub fn decode_base64(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let text = text.trim_end_matches('=').as_bytes();
    if text.len() % 4 == 1 {
        return None;
    }
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    for chunk in text.chunks(4) {
        let mut bits = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            bits |= value(c)? << (18 - 6 * k);
        }
        let bytes = bits.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Some(out)
}

/// Standard base64 with padding: what a data URI carries (for tools and tests that write glTF).
pub fn encode_base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let mut bits = 0u32;
        for (k, &b) in chunk.iter().enumerate() {
            bits |= u32::from(b) << (16 - 8 * k);
        }
        for k in 0..4 {
            match k <= chunk.len() {
                true => out.push(ALPHABET[(bits >> (18 - 6 * k) & 63) as usize] as char),
                false => out.push('='),
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if base64 is decoded wrongly at any padding length, or accepts a stray character.
    #[test]
    fn base64_round_trips() {
        assert_eq!(decode_base64("").unwrap(), b"");
        assert_eq!(decode_base64("Zg==").unwrap(), b"f");
        assert_eq!(decode_base64("Zm8=").unwrap(), b"fo");
        assert_eq!(decode_base64("Zm9v").unwrap(), b"foo");
        assert_eq!(decode_base64("Zm9vYg").unwrap(), b"foob");
        assert_eq!(decode_base64("/+8A").unwrap(), [0xff, 0xef, 0x00]);
        assert!(decode_base64("Zm9v!").is_none());
        assert!(decode_base64("Z").is_none());
        let bytes: Vec<u8> = (0..=255).collect();
        for n in 0..bytes.len() {
            assert_eq!(
                decode_base64(&encode_base64(&bytes[..n])).unwrap(),
                &bytes[..n]
            );
        }
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

    // Fails if a mirroring transform keeps w: the bitangent would point the wrong way.
    #[test]
    fn a_mirror_flips_the_tangents_sign() {
        let mirror = Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
        let n = Vec3::Z;
        let t = file_tangent(
            mirror,
            mirror.inverse().transpose(),
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            n,
        );
        // T = -x, B must stay +y: cross(z, -x) = -y, so w = -1.
        assert_eq!(t, Vec4::new(-1.0, 0.0, 0.0, -1.0));
        let (one, w_minus) = (Mat3::IDENTITY, Vec4::new(1.0, 0.0, 0.0, -1.0));
        let t = file_tangent(one, one, w_minus, n);
        assert_eq!(t, Vec4::new(1.0, 0.0, 0.0, -1.0));
    }
}
