//! A mesh in GL buffers: one VAO, one buffer per attribute the mesh has, and the element buffer.
//!
//! The attribute locations are the tutorial's (0 position, 1 UV, 2 normal, 3 tangent, 4 bitangent)
//! whatever the mesh holds: a mesh without tangents (e.g. one lit with per-pixel derivatives) gets no
//! tangent buffers and enables no tangent arrays.

use glow::HasContext;

use crate::common::vboindexer::{IndexedMesh, Indices};
use crate::gl::objects::Owned;
use crate::gl::Gl;
use crate::{Error, Result};

/// Attribute locations, as the tutorial's `layout(location = N)`.
pub const POSITION: u32 = 0;
pub const UV: u32 = 1;
pub const NORMAL: u32 = 2;
pub const TANGENT: u32 = 3;
pub const BITANGENT: u32 = 4;

/// One attribute buffer: where it goes and how many floats per vertex.
struct Attribute {
    location: u32,
    components: i32,
    buffer: Owned<glow::Buffer>,
}

/// The buffers and the VAO they are drawn through. Deleted with the value (fields drop in order:
/// the buffers, then the VAO that refers to them).
pub struct MeshBuffers {
    gl: Gl,
    attributes: Vec<Attribute>,
    elements: Owned<glow::Buffer>,
    vao: Owned<glow::VertexArray>,
    index_count: i32,
    index_type: u32,
}

impl MeshBuffers {
    /// Uploads every attribute the mesh has (an empty array = not there; positions are required)
    /// and the indices. Refuses a mesh whose arrays disagree in length or whose indices point past
    /// its vertices: drawing it would read outside the buffers.
    pub fn new(gl: &Gl, mesh: &IndexedMesh) -> Result<Self> {
        let n = mesh.vertices.len();
        // Each array as bytes, with its length in vertices.
        fn bytes<T: bytemuck::Pod>(array: &[T]) -> (&[u8], usize) {
            (bytemuck::cast_slice(array), array.len())
        }
        // (location, floats per vertex, name for errors, (bytes, vertices))
        type Array<'a> = (u32, i32, &'static str, (&'a [u8], usize));
        let arrays: [Array; 5] = [
            (POSITION, 3, "positions", bytes(&mesh.vertices)),
            (UV, 2, "UVs", bytes(&mesh.uvs)),
            (NORMAL, 3, "normals", bytes(&mesh.normals)),
            (TANGENT, 3, "tangents", bytes(&mesh.tangents)),
            (BITANGENT, 3, "bitangents", bytes(&mesh.bitangents)),
        ];
        for &(_, _, name, (_, len)) in &arrays[1..] {
            if len != 0 && len != n {
                return Err(Error::Mesh(format!("{n} vertices but {len} {name}")));
            }
        }
        if let Some(bad) = (0..mesh.indices.len())
            .map(|i| mesh.indices.get(i))
            .find(|&i| i as usize >= n)
        {
            return Err(Error::Mesh(format!("index {bad} is past the {n} vertices")));
        }
        let index_count = i32::try_from(mesh.indices.len()).map_err(|_| {
            Error::Mesh(format!(
                "{} indices are too many to draw",
                mesh.indices.len()
            ))
        })?;
        const PART: &str = "mesh buffers";
        let (index_bytes, index_type): (&[u8], u32) = match &mesh.indices {
            Indices::U16(v) => (bytemuck::cast_slice(v), glow::UNSIGNED_SHORT),
            Indices::U32(v) => (bytemuck::cast_slice(v), glow::UNSIGNED_INT),
        };
        // Every object is owned from the moment it exists: a failure drops what was made.
        let mut buffers = MeshBuffers {
            gl: gl.clone(),
            attributes: Vec::with_capacity(arrays.len()),
            elements: Owned::create(gl, PART)?,
            vao: Owned::create(gl, PART)?,
            index_count,
            index_type,
        };
        // SAFETY: the buffers are filled on the current context with slices that live through the
        // calls; the objects belong to `buffers`.
        unsafe {
            gl.bind_vertex_array(Some(buffers.vao.name()));
            for (location, components, _, (bytes, len)) in arrays {
                if len == 0 {
                    continue;
                }
                let buffer = Owned::create(gl, PART)?;
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(buffer.name()));
                gl.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::STATIC_DRAW);
                buffers.attributes.push(Attribute {
                    location,
                    components,
                    buffer,
                });
            }
            let elements = Some(buffers.elements.name());
            gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, elements);
            gl.buffer_data_u8_slice(glow::ELEMENT_ARRAY_BUFFER, index_bytes, glow::STATIC_DRAW);
        }
        Ok(buffers)
    }

    /// The locations this mesh enables, in order.
    pub fn locations(&self) -> Vec<u32> {
        self.attributes.iter().map(|a| a.location).collect()
    }

    /// The tutorial's draw: enable and point each attribute array, draw the elements, disable.
    pub fn draw(&self) {
        self.draw_indices(0, self.index_count);
    }

    /// [`MeshBuffers::draw`] of the triangles `triangles` only (one material of a model); a range
    /// past the end is cut to it.
    pub fn draw_triangles(&self, triangles: std::ops::Range<usize>) {
        let end = (3 * triangles.end).min(self.index_count as usize);
        let first = (3 * triangles.start).min(end);
        // Both fit: `index_count` is an i32.
        self.draw_indices(first as i32, (end - first) as i32);
    }

    /// Draws `count` indices from index `first`.
    fn draw_indices(&self, first: i32, count: i32) {
        let index_size = match self.index_type {
            glow::UNSIGNED_SHORT => 2,
            _ => 4,
        };
        let gl = &self.gl;
        // SAFETY: every buffer belongs to this context; the pointers describe the data uploaded in
        // `new`, whose indices were checked against the vertex count.
        unsafe {
            gl.bind_vertex_array(Some(self.vao.name()));
            for a in &self.attributes {
                gl.enable_vertex_attrib_array(a.location);
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(a.buffer.name()));
                gl.vertex_attrib_pointer_f32(a.location, a.components, glow::FLOAT, false, 0, 0);
            }
            gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(self.elements.name()));
            gl.draw_elements(
                glow::TRIANGLES,
                count,
                self.index_type,
                first.saturating_mul(index_size),
            );
            for a in &self.attributes {
                gl.disable_vertex_attrib_array(a.location);
            }
        }
    }
}
