//! A learner's own model (`--model FILE.obj`): an OBJ with the materials of its `.mtl`, or a glTF 2.0
//! file ([`gltf`]), read and placed for the tutorial's shaders (`NormalMapping.*`). An OBJ's frames
//! come from the tutorial's pipeline (`computeTangentBasis`, `indexVBO_TBN`) by default, a glTF's
//! from its own TANGENTs; [`load_shape`] reads a bake's HIGH, whose UVs are not used.
//!
//! Three things differ from the tutorial's `loadOBJ`, because a model exported by a modelling tool is
//! not the tutorial's cylinder:
//! * **V as written.** The tutorial negates V for its DDS files, stored upside down. A model's maps
//!   are ordinary pictures (top row first, V up the picture), so nothing is negated; the GL upload
//!   puts each map the way its sampler reads it (see [`maps`]).
//! * **Materials.** Each `usemtl` range keeps its own maps; triangles are grouped by material (in the
//!   order materials are first used) so that each material is one draw.
//! * **Placement.** The positions are scaled and moved onto the tutorial's cylinder's bounding sphere
//!   ([`TUTORIAL_CYLINDER_CENTER`], [`TUTORIAL_CYLINDER_RADIUS`]) as they are read. The tutorial's
//!   numbers then hold at any size: its 0.01 merge tolerance in `indexVBO_TBN`, its light (`lightPos`
//!   and the shader's `LightPower` 40 with its falloff), the camera's speed, the debug lines' length.
//!   [`Placement`] converts the file's own coordinates (e.g. `--light`) to the placed ones.

pub mod gltf;
pub mod maps;
pub mod mtl;
pub mod parts;

use crate::clock::Instant;
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};

use crate::common::objloader::{ObjMode, ObjRead, TriangleSoup};
use crate::pipeline::obj_parse::read_obj_threaded;
use crate::pipeline::{each_on_cores, runs_on_cores};
use crate::tangent_source::FileTangents;
use crate::{Error, Result};

/// The centre of the tutorial's cylinder's bounding box: it spans x and z from -1 to 1, y from 0 to 2.
pub const TUTORIAL_CYLINDER_CENTER: Vec3 = Vec3::new(0.0, 1.0, 0.0);
/// The distance from that centre to the cylinder's farthest vertex (its rims): √2.
pub const TUTORIAL_CYLINDER_RADIUS: f32 = std::f32::consts::SQRT_2;

/// Maps named on the command line, over every material's.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MapOverrides {
    /// `--diffuse FILE`.
    pub diffuse: Option<PathBuf>,
    /// `--normal-map FILE`.
    pub normal: Option<PathBuf>,
    /// `--specular FILE`.
    pub specular: Option<PathBuf>,
    /// `--height FILE`: a height map made into the normal map as `tutorial13 normalmap` does.
    pub height: Option<PathBuf>,
    /// `--strength S` for `--height` (the `normalmap` default, 8, when `None`).
    pub strength: Option<f32>,
}

impl MapOverrides {
    pub fn is_empty(&self) -> bool {
        *self == MapOverrides::default()
    }

    /// The normal map these overrides name (`--normal-map`, else `--height`), if any.
    pub fn normal_source(&self) -> Option<MapSource> {
        let strength = self
            .strength
            .unwrap_or(crate::normalmap::NormalMapOptions::default().strength);
        match (&self.normal, &self.height) {
            (Some(path), _) => Some(MapSource::command_line(path, "--normal-map")),
            (None, Some(path)) => Some(MapSource::Height {
                path: path.clone(),
                strength,
            }),
            (None, None) => None,
        }
    }
}

/// Where one of a material's three maps comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum MapSource {
    /// An image file. `named_by` says where it was named ("--diffuse", "map_Kd of material 'Brick'
    /// in brick.mtl"); a file a material names that is missing or cannot be decoded falls back to the
    /// neutral map with a notice, one named on the command line is an error.
    File {
        path: PathBuf,
        named_by: String,
        from_command_line: bool,
        /// The `-bm` of a bump statement: the normal map's x and y are scaled by it.
        bump_multiplier: Option<f32>,
    },
    /// A grey-scale height map made into a normal map in-process (`--height`).
    Height { path: PathBuf, strength: f32 },
    /// One colour (a material's `Kd` where it names no `map_Kd`).
    Colour([f32; 3]),
    /// A picture already read (a glTF's image: embedded, or a file beside it). `path` names it in
    /// messages; a picture that cannot be decoded is an error, as any glTF fault is.
    Bytes {
        bytes: std::sync::Arc<[u8]>,
        path: PathBuf,
        named_by: String,
        /// A glTF `normalTexture`'s `scale`: the normal map's x and y are scaled by it.
        bump_multiplier: Option<f32>,
    },
    /// White diffuse or specular (the tutorial's constant specular 0.3 = white × 0.3), or the flat
    /// normal (0, 0, 1).
    Neutral,
}

impl MapSource {
    pub fn command_line(path: &Path, flag: &str) -> Self {
        MapSource::File {
            path: path.to_path_buf(),
            named_by: flag.to_string(),
            from_command_line: true,
            bump_multiplier: None,
        }
    }
}

/// One material's maps.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    pub diffuse: MapSource,
    pub normal: MapSource,
    pub specular: MapSource,
}

/// The triangles of one material: soup triangles `triangles` (so indices `3 × triangles`).
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialRange {
    pub material: usize,
    pub triangles: std::ops::Range<usize>,
}

/// Where the file's coordinates were moved to: its bounding sphere (centre of the bounding box,
/// distance to the farthest vertex) onto the tutorial's cylinder's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// In the file's coordinates.
    pub center: Vec3,
    pub radius: f32,
}

impl Placement {
    /// Placed units per file unit.
    pub fn scale(&self) -> f32 {
        (TUTORIAL_CYLINDER_RADIUS as f64 / self.radius as f64) as f32
    }

    /// A point of the file (a vertex, or `--light`) where the program draws it.
    pub fn to_world(&self, p: Vec3) -> Vec3 {
        let scale = TUTORIAL_CYLINDER_RADIUS as f64 / self.radius as f64;
        let placed =
            (p.as_dvec3() - self.center.as_dvec3()) * scale + TUTORIAL_CYLINDER_CENTER.as_dvec3();
        placed.as_vec3()
    }

    /// A point where the program draws it, in the file's coordinates ([`Placement::to_world`]
    /// undone, up to rounding).
    pub fn to_file(&self, p: Vec3) -> Vec3 {
        let scale = TUTORIAL_CYLINDER_RADIUS as f64 / self.radius as f64;
        let file =
            (p.as_dvec3() - TUTORIAL_CYLINDER_CENTER.as_dvec3()) / scale + self.center.as_dvec3();
        file.as_vec3()
    }
}

/// A model, read and placed, its maps named but not yet decoded.
#[derive(Debug, Clone)]
pub struct Model {
    pub path: PathBuf,
    /// Placed positions, V as written, normals from the file or computed; grouped by material.
    pub soup: TriangleSoup,
    pub materials: Vec<Material>,
    /// In soup order, covering every triangle once.
    pub ranges: Vec<MaterialRange>,
    pub placement: Placement,
    /// The file has no normals: they were computed (unit length). A file's own are kept as written,
    /// as the tutorial's `loadOBJ` keeps them.
    pub normals_computed: bool,
    /// A glTF's own tangents, when some of its primitives supply them (MikkTSpace's for the
    /// others are computed when the mesh is built).
    pub file_tangents: Option<FileTangents>,
    /// What was filled in or left out (maps not named, normals computed, options ignored): one line
    /// each, for the log.
    pub notices: Vec<String>,
    /// Each soup triangle's index among the file's triangles (an OBJ's faces fanned as written, a
    /// glTF's primitives as the scene meets them) where grouping by material moved them; empty
    /// where the soup keeps the file's order. A bake pairs a cage's triangles with LOW's by it.
    pub file_order: Vec<u32>,
    /// A glTF's parts in the file's order ([`parts::Part`]); an OBJ's are read only when asked
    /// ([`parts::part_names`]), which takes another pass over its text.
    pub parts: Vec<parts::Part>,
}

/// Reads `path` and the `.mtl` files it names (relative to its folder), or a glTF file (`.gltf`,
/// `.glb`) and the buffers and images it names.
pub fn load_model(path: &Path, overrides: &MapOverrides) -> Result<Model> {
    let start = Instant::now();
    let bytes = crate::files::read(path).map_err(|e| Error::io(path, e))?;
    log::debug!(
        "{}: {:.1} MB read in {:.1} ms",
        path.display(),
        bytes.len() as f64 / 1e6,
        start.elapsed().as_secs_f64() * 1e3
    );
    load_model_bytes(&bytes, path, overrides, crate::files::read)
}

/// The model files the program reads, told apart by their extension: the one place a format is
/// named (a file of another extension is read as an OBJ where a model is asked for).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ with its `.mtl`.
    Obj,
    /// glTF 2.0, JSON (`.gltf`) or binary (`.glb`).
    Gltf,
}

impl Format {
    /// Each extension (lower case, without the dot) and its format, in the order they are listed.
    pub const EXTENSIONS: [(&'static str, Format); 3] = [
        ("obj", Format::Obj),
        ("gltf", Format::Gltf),
        ("glb", Format::Gltf),
    ];

    /// `path`'s format by its extension, in any case; `None` for any other file.
    pub fn of(path: &Path) -> Option<Format> {
        let extension = path.extension()?.to_str()?;
        let known = Format::EXTENSIONS.iter();
        known
            .filter(|(e, _)| e.eq_ignore_ascii_case(extension))
            .map(|&(_, format)| format)
            .next()
    }

    /// Whether `path` names a glTF file.
    pub fn is_gltf(path: &Path) -> bool {
        Format::of(path) == Some(Format::Gltf)
    }

    /// The extensions for a message: "an .obj, .gltf or .glb".
    pub fn listed() -> String {
        let names: Vec<String> = Format::EXTENSIONS
            .iter()
            .map(|(e, _)| format!(".{e}"))
            .collect();
        match names.split_last() {
            Some((last, [])) => format!("a {last}"),
            Some((last, rest)) => format!("an {} or {last}", rest.join(", ")),
            None => String::new(),
        }
    }
}

/// What a model's UVs are read for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Uvs {
    /// Its maps are laid with them: a file without is refused.
    Required,
    /// Never used (a bake's HIGH): a file without is read with (0, 0) at every corner.
    Optional,
}

/// [`load_model`] for a model whose shape alone is used (a bake's HIGH). A sculpt is often
/// exported without a UV layout: an OBJ none of whose faces names a UV is read with (0, 0) at
/// every corner, in the same one pass ([`ObjMode::Shape`]), and a glTF primitive without its UV
/// set gets the same.
pub fn load_shape(path: &Path) -> Result<Model> {
    let bytes = crate::files::read(path).map_err(|e| Error::io(path, e))?;
    load_shape_bytes(&bytes, path, crate::files::read)
}

/// [`load_shape`] on the model's bytes; `read_file` as [`load_model_bytes`]'s.
pub fn load_shape_bytes(
    bytes: &[u8],
    path: &Path,
    read_file: impl Fn(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<Model> {
    let overrides = MapOverrides::default();
    if Format::is_gltf(path) {
        return gltf::load_gltf(bytes, path, &overrides, Uvs::Optional, &read_file);
    }
    load_obj_model(bytes, path, &overrides, &read_file, ObjMode::Shape)
}

/// [`load_model`] on the model's bytes (an OBJ, or a glTF by `path`'s extension); `read_mtl` reads
/// a file the model names: an OBJ's `.mtl`, a glTF's buffers and images (the fuzz harness gives its
/// own).
pub fn load_model_bytes(
    bytes: &[u8],
    path: &Path,
    overrides: &MapOverrides,
    read_mtl: impl Fn(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<Model> {
    if Format::is_gltf(path) {
        return gltf::load_gltf(bytes, path, overrides, Uvs::Required, &read_mtl);
    }
    load_obj_model(bytes, path, overrides, &read_mtl, ObjMode::Model)
}

/// An OBJ as a model ([`ObjMode::Model`]) or as a shape ([`ObjMode::Shape`]: no UVs read as (0, 0)).
fn load_obj_model(
    bytes: &[u8],
    path: &Path,
    overrides: &MapOverrides,
    read_mtl: &impl Fn(&Path) -> std::io::Result<Vec<u8>>,
    mode: ObjMode,
) -> Result<Model> {
    let (read, mut notices, material_files) = read_obj_and_mtls(bytes, path, read_mtl, mode)?;
    let start = Instant::now();

    let mut soup = read.soup;
    if read.normals_missing {
        soup.normals = smooth_normals(&soup.vertices, &read.position_indices);
        notices.push(format!(
            "{}: no vertex normals (vn): smooth normals computed (angle-weighted per position)",
            path.display()
        ));
    }

    let (materials, triangle_materials) = obj_materials(
        &read.materials,
        &read.triangle_materials,
        &material_files,
        overrides,
        path,
        &mut notices,
    );

    let (soup, ranges, file_order) = group_by_material(soup, &triangle_materials);
    let placement = placement(&soup.vertices).ok_or_else(|| Error::Obj {
        path: path.to_path_buf(),
        reason: "every face is at one point: a model needs some size to be framed and lit".into(),
    })?;
    let mut soup = soup;
    each_on_cores(&mut soup.vertices, |p| *p = placement.to_world(*p));
    log::debug!(
        "{}: normals, materials, grouping and placement in {:.1} ms",
        path.display(),
        start.elapsed().as_secs_f64() * 1e3
    );
    if read.uvs_missing {
        notices.push(format!(
            "{}: no UVs: read with (0, 0) at every corner (its UVs are not used here)",
            path.display()
        ));
    }
    Ok(Model {
        path: path.to_path_buf(),
        soup,
        materials,
        ranges,
        placement,
        normals_computed: read.normals_missing,
        file_tangents: None,
        notices,
        file_order,
        parts: Vec::new(),
    })
}

/// The OBJ's soup and materials, with the notices of `.mtl` files that could not be read and the
/// `.mtl` file each material comes from.
fn read_obj_and_mtls(
    bytes: &[u8],
    path: &Path,
    read_mtl: &impl Fn(&Path) -> std::io::Result<Vec<u8>>,
    mode: ObjMode,
) -> Result<(ObjRead, Vec<String>, HashMap<String, PathBuf>)> {
    let folder = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let notices = RefCell::new(Vec::new());
    // Each material's .mtl file, for the paths its maps give.
    let material_files = RefCell::new(HashMap::<String, PathBuf>::new());
    let load_mtl = |name: &Path| -> tobj::MTLLoadResult {
        let mtl_path = folder.join(name.to_string_lossy().replace('\\', "/"));
        let parsed = read_mtl(&mtl_path)
            .map_err(|e| e.to_string())
            .and_then(|bytes| {
                let text = String::from_utf8_lossy(&bytes);
                mtl::check_mtl(&text).map_err(|e| format!("malformed MTL: {e}"))?;
                tobj::load_mtl_buf(&mut bytes.as_slice()).map_err(|e| format!("malformed MTL: {e}"))
            });
        match parsed {
            Ok((materials, names)) => {
                let mut files = material_files.borrow_mut();
                for m in &materials {
                    files.insert(m.name.clone(), mtl_path.clone());
                }
                Ok((materials, names))
            }
            Err(reason) => {
                notices.borrow_mut().push(format!(
                    "{}: {reason}; its materials get neutral maps",
                    mtl_path.display()
                ));
                Ok((Vec::new(), Default::default()))
            }
        }
    };
    let read = read_obj_threaded(bytes, path, mode, load_mtl, None)?;
    Ok((read, notices.into_inner(), material_files.into_inner()))
}

/// The OBJ's materials with `overrides` applied, and each triangle's material (an index into them,
/// from `triangle_materials`, an index into `tobj_materials` or none).
fn obj_materials(
    tobj_materials: &[tobj::Material],
    triangle_materials: &[Option<usize>],
    material_files: &HashMap<String, PathBuf>,
    overrides: &MapOverrides,
    path: &Path,
    notices: &mut Vec<String>,
) -> (Vec<Material>, Vec<usize>) {
    // The materials, then a neutral one for triangles without (only if there are such triangles).
    let mut materials: Vec<Material> = tobj_materials
        .iter()
        .map(|m| material(m, material_files.get(&m.name), notices))
        .collect();
    let unnamed = materials.len();
    let triangle_materials: Vec<usize> = triangle_materials
        .iter()
        .map(|m| m.filter(|&i| i < unnamed).unwrap_or(unnamed))
        .collect();
    if triangle_materials.contains(&unnamed) {
        notices.push(format!(
            "{}: {} without a material (no usemtl, or one no .mtl defines): white diffuse, flat \
             normal map, specular 0.3 (the tutorial's constant)",
            path.display(),
            if unnamed == 0 {
                "every face is"
            } else {
                "some faces are"
            }
        ));
        materials.push(Material {
            name: "(none)".into(),
            diffuse: MapSource::Neutral,
            normal: MapSource::Neutral,
            specular: MapSource::Neutral,
        });
    }
    for material in &mut materials {
        apply_overrides(material, overrides);
    }
    (materials, triangle_materials)
}

/// One tobj material's maps, paths resolved against its `.mtl` file's folder.
fn material(m: &tobj::Material, mtl: Option<&PathBuf>, notices: &mut Vec<String>) -> Material {
    let mtl_name = mtl.map_or_else(|| "the .mtl".to_string(), |p| p.display().to_string());
    let folder = mtl.and_then(|p| p.parent()).unwrap_or(Path::new(""));
    let mut map = |keyword: &str, statement: Option<&String>| -> Option<MapSource> {
        let statement = statement?;
        let named_by = format!("{keyword} of material '{}' in {mtl_name}", m.name);
        match mtl::parse_texture_statement(statement) {
            Ok(s) => {
                if !s.ignored.is_empty() {
                    notices.push(format!("{named_by}: ignored {}", s.ignored.join(", ")));
                }
                Some(MapSource::File {
                    path: resolve(folder, &s.file),
                    named_by,
                    from_command_line: false,
                    bump_multiplier: s.bump_multiplier,
                })
            }
            Err(reason) => {
                notices.push(format!("{named_by}: {reason}; left out"));
                None
            }
        }
    };
    let diffuse = map("map_Kd", m.diffuse_texture.as_ref());
    // Blender writes a normal map as map_Bump (with -bm); `norm` is the PBR extension's keyword.
    let normal = map("map_Bump", m.normal_texture.as_ref())
        .or_else(|| map("norm", m.unknown_param.get("norm")));
    let specular = map("map_Ks", m.specular_texture.as_ref());
    let mut missing = Vec::new();
    let diffuse = diffuse.unwrap_or_else(|| match m.diffuse {
        Some(kd) => MapSource::Colour(kd),
        None => {
            missing.push("no map_Kd or Kd: white diffuse");
            MapSource::Neutral
        }
    });
    let normal = normal.unwrap_or_else(|| {
        missing.push("no normal map (map_Bump, bump or norm): the flat normal (0, 0, 1)");
        MapSource::Neutral
    });
    let specular = specular.unwrap_or_else(|| {
        missing.push("no map_Ks: specular 0.3 (the tutorial's constant)");
        MapSource::Neutral
    });
    if !missing.is_empty() {
        notices.push(format!(
            "material '{}' in {mtl_name}: {}",
            m.name,
            missing.join("; ")
        ));
    }
    Material {
        name: m.name.clone(),
        diffuse,
        normal,
        specular,
    }
}

/// A map's file: as written, relative to the `.mtl`'s folder; else its name alone in that folder
/// (exporters often write the absolute path of the machine the model was made on).
fn resolve(folder: &Path, file: &str) -> PathBuf {
    let written = folder.join(file);
    if crate::files::is_file(&written) {
        return written;
    }
    match Path::new(file).file_name() {
        Some(name) if crate::files::is_file(&folder.join(name)) => folder.join(name),
        _ => written,
    }
}

pub(crate) fn apply_overrides(material: &mut Material, overrides: &MapOverrides) {
    if let Some(path) = &overrides.diffuse {
        material.diffuse = MapSource::command_line(path, "--diffuse");
    }
    if let Some(source) = overrides.normal_source() {
        material.normal = source;
    }
    if let Some(path) = &overrides.specular {
        material.specular = MapSource::command_line(path, "--specular");
    }
}

/// The soup with its triangles grouped by material (stable: each material's triangles keep their
/// order; materials in the order they are first used), the ranges, and each new triangle's index in
/// `soup` (empty when nothing moved: [`Model::file_order`]). A counting sort: linear in the
/// triangles, and no copy at all when the soup is one run of a material already.
pub(crate) fn group_by_material(
    soup: TriangleSoup,
    triangle_materials: &[usize],
) -> (TriangleSoup, Vec<MaterialRange>, Vec<u32>) {
    let count = triangle_materials.iter().max().map_or(0, |&m| m + 1);
    // Each material's rank by first use, and its number of triangles.
    let mut rank = vec![usize::MAX; count];
    let mut order = Vec::new();
    let mut sizes = vec![0usize; count];
    for &m in triangle_materials {
        if rank[m] == usize::MAX {
            rank[m] = order.len();
            order.push(m);
        }
        sizes[m] += 1;
    }
    let mut ranges = Vec::with_capacity(order.len());
    let mut start = 0;
    for &m in &order {
        ranges.push(MaterialRange {
            material: m,
            triangles: start..start + sizes[m],
        });
        start += sizes[m];
    }
    let grouped = triangle_materials
        .windows(2)
        .all(|w| w[0] == w[1] || rank[w[0]] < rank[w[1]]);
    if grouped {
        return (soup, ranges, Vec::new());
    }
    let mut next: Vec<usize> = vec![0; count];
    for range in &ranges {
        next[range.material] = range.triangles.start;
    }
    let corners = soup.vertices.len();
    let mut out = TriangleSoup {
        vertices: vec![Vec3::ZERO; corners],
        uvs: vec![glam::Vec2::ZERO; corners],
        normals: vec![Vec3::ZERO; soup.normals.len()],
    };
    let mut file_order = vec![0u32; triangle_materials.len()];
    for (t, &m) in triangle_materials.iter().enumerate() {
        let (from, to) = (3 * t..3 * t + 3, 3 * next[m]..3 * next[m] + 3);
        file_order[next[m]] = t as u32;
        next[m] += 1;
        out.vertices[to.clone()].copy_from_slice(&soup.vertices[from.clone()]);
        out.uvs[to.clone()].copy_from_slice(&soup.uvs[from.clone()]);
        out.normals[to].copy_from_slice(&soup.normals[from]);
    }
    (out, ranges, file_order)
}

/// The bounding sphere the model is placed by, or `None` if it has no size (or no finite one).
pub(crate) fn placement(vertices: &[Vec3]) -> Option<Placement> {
    // Each pass a run per core: a minimum or a maximum is the same taken in any order.
    let boxes = runs_on_cores(vertices, |run| {
        let (mut min, mut max) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        for p in run {
            min = min.min(p.as_dvec3());
            max = max.max(p.as_dvec3());
        }
        (min, max)
    });
    let (min, max) = (boxes.into_iter()).fold(
        (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
        |(min, max), (lo, hi)| (min.min(lo), max.max(hi)),
    );
    let center = (min + max) * 0.5;
    let radius = runs_on_cores(vertices, |run| {
        (run.iter())
            .map(|p| p.as_dvec3().distance(center))
            .fold(0.0, f64::max)
    })
    .into_iter()
    .fold(0.0, f64::max);
    let placement = Placement {
        center: center.as_vec3(),
        radius: radius as f32,
    };
    // Too small for f32 (or zero), or too large: nothing sensible to scale by.
    let usable = placement.radius.is_normal() && placement.scale().is_normal();
    usable.then_some(placement)
}

/// Smooth normals for a soup whose file gave none: each face's normal, weighted by its corner's
/// angle, summed over every corner that shares a position index in the file, normalized.
pub fn smooth_normals(vertices: &[Vec3], position_indices: &[u32]) -> Vec<Vec3> {
    let count = position_indices.iter().max().map_or(0, |&m| m as usize + 1);
    let mut sums = vec![DVec3::ZERO; count];
    for (triangle, indices) in vertices
        .chunks_exact(3)
        .zip(position_indices.chunks_exact(3))
    {
        let [a, b, c] = [0, 1, 2].map(|k| triangle[k].as_dvec3());
        let Some(face) = (b - a).cross(c - a).try_normalize() else {
            continue; // a degenerate triangle has no direction to give
        };
        for (k, &index) in indices.iter().enumerate() {
            let p = [a, b, c][k];
            let (e1, e2) = ([a, b, c][(k + 1) % 3] - p, [a, b, c][(k + 2) % 3] - p);
            let angle = e1.angle_between(e2);
            if angle.is_finite() {
                sums[index as usize] += face * angle;
            }
        }
    }
    position_indices
        .iter()
        .map(|&i| {
            sums[i as usize]
                .try_normalize()
                .unwrap_or(DVec3::Z)
                .as_vec3()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if the placement does not put the bounding sphere on the tutorial's cylinder's, or
    // loses precision far from the origin.
    #[test]
    fn placement_maps_the_sphere_onto_the_cylinders() {
        let vertices = [Vec3::new(1000.0, 0.0, 0.0), Vec3::new(1200.0, 0.0, 0.0)];
        let p = placement(&vertices).unwrap();
        assert_eq!(p.center, Vec3::new(1100.0, 0.0, 0.0));
        assert_eq!(p.radius, 100.0);
        let world = p.to_world(Vec3::new(1200.0, 0.0, 0.0));
        assert!((world - Vec3::new(TUTORIAL_CYLINDER_RADIUS, 1.0, 0.0)).length() < 1e-6);
        assert!(placement(&[Vec3::ONE, Vec3::ONE]).is_none());
        assert!(placement(&[Vec3::splat(-3e38), Vec3::splat(3e38)]).is_none());
    }

    /// Fails if the placement of a sculpt-sized model, measured a run per core, is not the one
    /// measured in one pass (its centre and radius to the bit), zeros of both signs included.
    #[test]
    fn a_large_models_placement_is_the_one_pass_placement() {
        let mut next = crate::bake::xorshift(0x91ace);
        let mut unit = move || (next() >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0;
        let mut vertices: Vec<Vec3> = (0..300_001)
            .map(|_| Vec3::new(unit() * 3.0 + 1.0, unit() * 0.5, unit() * 7.0 - 2.0))
            .collect();
        vertices[12_345] = Vec3::new(-0.0, 0.0, -0.0);
        vertices[250_000] = Vec3::new(0.0, -0.0, 0.0);
        let (mut min, mut max) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        for p in &vertices {
            min = min.min(p.as_dvec3());
            max = max.max(p.as_dvec3());
        }
        let center = (min + max) * 0.5;
        let radius = (vertices.iter())
            .map(|p| p.as_dvec3().distance(center))
            .fold(0.0, f64::max);
        let placed = placement(&vertices).unwrap();
        assert_eq!(
            placed.center.to_array().map(f32::to_bits),
            center.as_vec3().to_array().map(f32::to_bits)
        );
        assert_eq!(placed.radius.to_bits(), (radius as f32).to_bits());
    }

    // Fails if interleaved materials are not grouped in first-use order with each one's triangles
    // kept in order, if the ranges do not match, or if a grouped triangle's file index is not the
    // one it came from.
    #[test]
    fn triangles_are_grouped_by_material_in_first_use_order() {
        let triangle = |k: f32| [Vec3::splat(k); 3];
        let soup = TriangleSoup {
            vertices: (0..5).flat_map(|t| triangle(t as f32)).collect(),
            uvs: vec![glam::Vec2::ZERO; 15],
            normals: vec![Vec3::Z; 15],
        };
        let (grouped, ranges, file_order) = group_by_material(soup.clone(), &[2, 0, 2, 1, 0]);
        let order: Vec<f32> = grouped.vertices.chunks(3).map(|c| c[0].x).collect();
        assert_eq!(order, [0.0, 2.0, 1.0, 4.0, 3.0]);
        // Each grouped triangle's index in the file: the same as the positions tell (and for an
        // order that is not its own inverse).
        assert_eq!(file_order, [0, 2, 1, 4, 3]);
        let soup6 = TriangleSoup {
            vertices: (0..6).flat_map(|t| triangle(t as f32)).collect(),
            uvs: vec![glam::Vec2::ZERO; 18],
            normals: vec![Vec3::Z; 18],
        };
        let (grouped, _, file_order) = group_by_material(soup6, &[1, 0, 0, 1, 2, 0]);
        let order: Vec<u32> = grouped.vertices.chunks(3).map(|c| c[0].x as u32).collect();
        assert_eq!(file_order, order);
        assert_eq!(file_order, [0, 3, 1, 2, 5, 4]);
        let spans: Vec<(usize, std::ops::Range<usize>)> = ranges
            .iter()
            .map(|r| (r.material, r.triangles.clone()))
            .collect();
        assert_eq!(spans, [(2, 0..2), (0, 2..4), (1, 4..5)]);
        // Already grouped: the same soup back.
        let (same, ranges, file_order) = group_by_material(soup.clone(), &[1, 1, 0, 0, 0]);
        assert_eq!(same, soup);
        assert_eq!(ranges.len(), 2);
        assert!(file_order.is_empty());
    }

    // Fails if the smooth normals of a model without `vn` are keyed by anything but the file's
    // position index: tobj numbers positions per object (and per material), so the first corner of
    // the second object shared its sums with the first object's, and the two walls' normals came
    // out diagonal.
    #[test]
    fn smooth_normals_of_objects_stay_apart() {
        let text = "o Floor\nv 0 0 0\nv 1 0 0\nv 1 0 -1\nv 0 0 -1\nvt 0 0\nf 1/1 2/1 3/1 4/1\n\
                    o Wall\nv 3 0 0\nv 3 0 -1\nv 3 1 -1\nv 3 1 0\nf 5/1 6/1 7/1 8/1\n";
        let no_mtl = |_: &Path| Err(std::io::ErrorKind::NotFound.into());
        let model = load_model_bytes(
            text.as_bytes(),
            Path::new("two.obj"),
            &MapOverrides::default(),
            no_mtl,
        )
        .unwrap();
        assert!(model.normals_computed);
        let (floor, wall) = model.soup.normals.split_at(6);
        assert!(floor.iter().all(|&n| n == Vec3::Y), "{floor:?}");
        assert!(wall.iter().all(|&n| n == Vec3::X), "{wall:?}");
    }

    // Fails if a corner's normal is not the angle-weighted mean of its faces' normals.
    #[test]
    fn smooth_normals_weight_faces_by_angle() {
        // Two faces of a unit cube's corner at the origin: the xy face (normal +z) and the yz face
        // (normal +x), each a right triangle with its right angle at the shared corner.
        let vertices = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ZERO, Vec3::Y, Vec3::Z];
        let indices = [0, 1, 2, 0, 2, 3];
        let normals = smooth_normals(&vertices, &indices);
        let expected = Vec3::new(1.0, 0.0, 1.0).normalize();
        assert!((normals[0] - expected).length() < 1e-6, "{}", normals[0]);
        // The shared edge's other end (index 2) has 45° in each face: the same mean.
        assert!((normals[2] - expected).length() < 1e-6, "{}", normals[2]);
        assert_eq!(normals[1], Vec3::Z);
        assert_eq!(normals[5], Vec3::X);
    }
}
