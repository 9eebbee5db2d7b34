//! The TBN debug lines' cost per frame: the tutorial's immediate mode against the core-profile line
//! shader, on a 150k-triangle cylinder, headless on llvmpipe:
//! `cargo bench -p tutorial13-benches --bench debug_lines`.
//!
//! Each sample is one draw of the lines alone, finished with glFinish; the cylinder is drawn once
//! beforehand so the lines are depth-tested against it as in a real frame. Immediate mode sends
//! 3 × 2 vertices per index (2.7 million glVertex3fv calls here) every frame; the shader path draws
//! one buffer uploaded once. Both submit the same 1.35 million lines.
//!
//! Measured on llvmpipe (Mesa 22.3.6, 2 cores): about 80 ms for either path from the tutorial's
//! camera and 160 ms for either with the whole cylinder in view. On llvmpipe the cost is Mesa's
//! per-line vertex processing, clipping and setup on the calling thread (three quarters of the
//! profile), which both paths pay alike; the immediate-mode calls themselves are a small share. The
//! shader path's saving is the CPU submission, which shows on a GPU, not here.

use std::path::{Path, PathBuf};
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use glow::HasContext;
use tutorial13::assets::obj_text::grid_cylinder_obj_text;
use tutorial13::common::shader::crate_shader_dir;
use tutorial13::debug::lines::{DebugLines, LineMode};
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::gl::{gl_errors, Profile};
use tutorial13::scenes::cylinder::tutorial13::LIGHT_POS;
use tutorial13::scenes::cylinder::Cylinder;
use tutorial13::scenes::SceneOptions;

/// 375 segments × 200 rings × 2 = 150 000 triangles; vertices stay more than 0.01 apart (0.063 around,
/// 0.05 along), so the tutorial's indexer keeps them all.
const SEGMENTS: u32 = 375;
const RINGS: u32 = 200;

/// A folder with the large cylinder and the crate's own textures, as HeadlessRenderer loads them.
fn large_scene() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tutorial13-bench-lines-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("cylinder.obj"),
        grid_cylinder_obj_text(SEGMENTS, RINGS, 3.75, 10.0, 2.0),
    )
    .unwrap();
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    for file in ["diffuse.DDS", "specular.DDS", "normal.bmp"] {
        std::fs::copy(assets.join(file), dir.join(file)).unwrap();
    }
    dir
}

fn lines(c: &mut Criterion) {
    let dir = large_scene();
    let mut renderer = HeadlessRenderer::new(&HeadlessOptions {
        scene: SceneOptions {
            assets: Some(dir.clone()),
            ..Default::default()
        },
        width: 512,
        height: 384,
        profile: Profile::Compat,
        ..Default::default()
    })
    .expect("a compatibility-profile context on llvmpipe");
    let _ = std::fs::remove_dir_all(&dir);
    let mesh = &renderer.scene_ref::<Cylinder>().tutorial.mesh;
    let triangles = mesh.indices.len() / 3;
    assert!(triangles >= 150_000, "{triangles} triangles");
    let context = renderer.host.gl();
    let make = |mode| {
        let lines = DebugLines::new(
            &context.gl,
            &context.extensions,
            mesh,
            LIGHT_POS,
            Some(mode),
            Some(&crate_shader_dir()),
        )
        .unwrap();
        assert_eq!(lines.mode(), mode);
        lines
    };
    let (legacy, shader) = (make(LineMode::Legacy), make(LineMode::Shader));

    let gl = renderer.host.gl().gl.clone();
    let model = renderer.scene_ref::<Cylinder>().tutorial.model_matrix;
    let mut group = c.benchmark_group(format!("debug_lines_{}k_triangles", triangles / 1000));
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(10));
    // The tutorial's camera is 1.25 from the surface: most lines are clipped away. From far back the
    // whole cylinder is in view and every line is rasterized.
    for (camera, position) in [
        ("tutorial_camera", Vec3::new(0.0, 0.0, 5.0)),
        ("whole_cylinder", Vec3::new(0.0, 5.0, 30.0)),
    ] {
        renderer.host.controls.position = position;
        renderer.render().unwrap();
        let (projection, view) = (
            renderer.host.controls.projection_matrix(),
            renderer.host.controls.view_matrix(),
        );
        for (name, lines) in [("immediate_mode", &legacy), ("line_shader", &shader)] {
            group.bench_function(format!("{camera}/{name}"), |b| {
                b.iter(|| {
                    lines.draw(projection, view, model);
                    // SAFETY: waits for the current context's queued work.
                    unsafe { gl.finish() };
                })
            });
        }
    }
    group.finish();
    let errors = gl_errors(&gl);
    assert!(errors.is_empty(), "GL errors: {errors:x?}");
}

criterion_group!(benches, lines);
criterion_main!(benches);
