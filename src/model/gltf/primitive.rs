//! One primitive read: its accessors checked against their buffers, its attributes read and taken
//! to the scene's space, and its indices expanded into corners.

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

/// One primitive's corners, transformed to the scene's space.
pub(super) struct Primitive {
    pub(super) vertices: Vec<Vec3>,
    pub(super) uvs: Vec<Vec2>,
    pub(super) normals: Vec<Vec3>,
    pub(super) tangents: Option<Vec<[f32; 4]>>,
    pub(super) normals_computed: bool,
}

/// What a primitive's checked accessors give: the vertex count, and whether its normals and its
/// tangents are read.
struct Checked {
    count: usize,
    normals: bool,
    tangents: bool,
}

/// A primitive's attributes per vertex, in the scene's space (the normals made unit).
struct Attributes {
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    normals: Option<Vec<Vec3>>,
    tangents: Option<Vec<Vec4>>,
}

/// A primitive's corners, in `world`, with UV set `set` (`TEXCOORD_set`); with `None`, every
/// A primitive's corners, in `world`, with UV set `set` (`TEXCOORD_set`); with `None`, every
/// corner's UV is (0, 0).
pub(super) fn read_primitive(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    world: Mat4,
    at: &str,
    set: Option<u32>,
) -> Result<Primitive, String> {
    let checked = check_attributes(primitive, buffers, at, set)?;
    let clock = crate::clock::Instant::now();
    let attributes = read_attributes(primitive, buffers, world, at, set, &checked)?;
    let indices = read_indices(primitive, buffers, at, checked.count)?;
    log::trace!(
        "{at}: accessors read in {:.1} ms",
        clock.elapsed().as_secs_f64() * 1e3
    );
    let clock = crate::clock::Instant::now();
    let primitive = expand(attributes, &indices, world);
    log::trace!(
        "{at}: corners expanded in {:.1} ms",
        clock.elapsed().as_secs_f64() * 1e3
    );
    Ok(primitive)
}

/// Checks the primitive's mode and the accessors of the attributes read (POSITION, the UV set,
/// NORMAL, TANGENT): their types, their ranges, and one element per vertex in each.
fn check_attributes(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    at: &str,
    set: Option<u32>,
) -> Result<Checked, String> {
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
    Ok(Checked {
        count,
        normals: normals.is_some(),
        tangents: tangents.is_some(),
    })
}

/// Reads the checked attributes per vertex: positions by `world`, V turned into the OBJ's (or
/// (0, 0) without a UV set), normals by its inverse transpose, the file's tangents as
/// [`file_tangent`] takes them.
fn read_attributes(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    world: Mat4,
    at: &str,
    set: Option<u32>,
    checked: &Checked,
) -> Result<Attributes, String> {
    let count = checked.count;
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
    let file_normals: Option<Vec<Vec3>> = match checked.normals {
        true => Some(
            reader
                .read_normals()
                .ok_or_else(out_of_range)?
                .map(Vec3::from)
                .collect(),
        ),
        false => None,
    };
    // Directions go across by the transform, normals by its inverse transpose: both once a primitive.
    let m = Mat3::from_mat4(world);
    let normal_matrix = m.inverse().transpose();
    let tangents: Option<Vec<Vec4>> = match (checked.tangents, &file_normals) {
        (true, Some(normals)) => Some(
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
    Ok(Attributes {
        positions,
        uvs,
        normals,
        tangents,
    })
}

/// The primitive's indices (0, 1, 2, … without an accessor), checked to make whole triangles of
/// the `count` vertices.
fn read_indices(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    at: &str,
    count: usize,
) -> Result<Vec<u32>, String> {
    let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let out_of_range = || format!("{at}: an accessor is out of its buffer");
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
    Ok(indices)
}

/// One entry per corner of the triangles `indices` make, in the order that keeps them
/// counter-clockwise; flat normals where the file has none.
fn expand(attributes: Attributes, indices: &[u32], world: Mat4) -> Primitive {
    let Attributes {
        positions,
        uvs,
        normals,
        tangents,
    } = attributes;
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
    Primitive {
        uvs: corners.iter().map(|&i| uvs[i]).collect(),
        normals,
        tangents: tangents.map(|t| corners.iter().map(|&i| t[i].to_array()).collect()),
        vertices,
        normals_computed,
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
pub(super) fn view_bytes<'b>(
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

#[cfg(test)]
mod tests {
    use super::*;

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
