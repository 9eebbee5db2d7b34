//! The GL helpers every scene shares: mesh buffers that take only the attributes a mesh has, and an
//! offscreen target backed by a texture that a later pass can sample. Headless on llvmpipe.

use glam::{Vec2, Vec3};
use glow::HasContext;
use tutorial13::common::vboindexer::{IndexedMesh, Indices};
use tutorial13::gl::buffers::MeshBuffers;
use tutorial13::gl::context::HeadlessContext;
use tutorial13::gl::offscreen::{ColorBuffer, OffscreenTarget};
use tutorial13::gl::{gl_errors, Profile};
use tutorial13::Error;

fn context() -> HeadlessContext {
    HeadlessContext::new(Profile::Core, false).expect("a core context on llvmpipe")
}

/// One triangle, with or without tangent arrays.
fn triangle(tangents: bool) -> IndexedMesh {
    let frame = |v: Vec3| if tangents { vec![v; 3] } else { Vec::new() };
    IndexedMesh {
        indices: Indices::from_u32(vec![0, 1, 2], 3),
        vertices: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y],
        normals: vec![Vec3::Z; 3],
        tangents: frame(Vec3::X),
        bitangents: frame(Vec3::Y),
    }
}

// Fails if a mesh without tangents still gets tangent arrays (a shader without them would read
// unbound attributes), if a full mesh loses one, or if drawing either raises a GL error.
#[test]
fn buffers_enable_only_the_attributes_a_mesh_has() {
    let context = context();
    let gl = context.gl();
    let target = OffscreenTarget::new(gl, 8, 8).unwrap();
    target.bind();
    for (tangents, expected) in [(true, vec![0, 1, 2, 3, 4]), (false, vec![0, 1, 2])] {
        let buffers = MeshBuffers::new(gl, &triangle(tangents)).unwrap();
        assert_eq!(buffers.locations(), expected);
        buffers.draw();
        assert_eq!(gl_errors(gl), Vec::<u32>::new(), "tangents: {tangents}");
        // The draw leaves no array enabled behind it, so the next mesh starts clean.
        for location in 0..5 {
            // SAFETY: a plain query on the current context.
            let mut enabled = [0.0f32; 4];
            unsafe {
                gl.get_vertex_attrib_parameter_f32_slice(
                    location,
                    glow::VERTEX_ATTRIB_ARRAY_ENABLED,
                    &mut enabled,
                )
            };
            assert_eq!(enabled[0], 0.0, "location {location} left enabled");
        }
    }
}

// Fails if a mesh whose arrays disagree, or whose indices point past its vertices, is uploaded
// instead of refused with a Mesh error naming the problem.
#[test]
fn buffers_refuse_inconsistent_meshes() {
    let context = context();
    let mut short = triangle(true);
    short.tangents.pop();
    let mut past = triangle(false);
    past.indices = Indices::U32(vec![0, 1, 3]);
    for (mesh, needle) in [(short, "3 vertices but 2 tangents"), (past, "index 3")] {
        match MeshBuffers::new(context.gl(), &mesh) {
            Err(Error::Mesh(reason)) => assert!(reason.contains(needle), "{reason}"),
            Err(other) => panic!("expected a Mesh error, got {other}"),
            Ok(_) => panic!("{needle}: accepted"),
        }
    }
}

// Fails if a texture-backed target cannot be drawn into, or if its texture does not hold what was
// drawn (the comparison views sample it).
#[test]
fn a_texture_target_holds_the_frame() {
    let context = context();
    let gl = context.gl();
    let target = OffscreenTarget::with_color(gl, 4, 2, ColorBuffer::Texture).unwrap();
    let texture = target.texture().expect("a texture target has a texture");
    assert!(OffscreenTarget::new(gl, 4, 2).unwrap().texture().is_none());
    target.bind();
    let mut texels = vec![0u8; 4 * 2 * 4];
    // SAFETY: clears and reads on the current context; `texels` holds the 4×2 RGBA8 level.
    unsafe {
        gl.clear_color(1.0, 0.5, 0.0, 1.0);
        gl.clear(glow::COLOR_BUFFER_BIT);
        gl.bind_texture(glow::TEXTURE_2D, Some(texture));
        gl.pixel_store_i32(glow::PACK_ALIGNMENT, 1);
        gl.get_tex_image(
            glow::TEXTURE_2D,
            0,
            glow::RGBA,
            glow::UNSIGNED_BYTE,
            glow::PixelPackData::Slice(Some(&mut texels)),
        );
    }
    assert_eq!(gl_errors(gl), Vec::<u32>::new());
    assert!(
        texels.chunks(4).all(|t| t == [255, 128, 0, 255]),
        "{texels:?}"
    );
    assert!(target
        .read_rgba()
        .pixels()
        .all(|p| p.0 == [255, 128, 0, 255]));
}
