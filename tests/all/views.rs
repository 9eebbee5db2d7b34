//! "Debugging with colors" and the tutorial's experiments, checked on rendered frames: each colour view
//! against its formula, equivalent shader paths against each other, and the switches where they must
//! (and must not) change the picture.

use crate::common::*;
use glam::{Mat3, Vec3};
use image::RgbImage;
use tutorial13::assets::obj_text::grid_cylinder_obj_text;
use tutorial13::common::controls::Controls;
use tutorial13::common::tangentspace::{compute_tangent_basis, TangentOptions};
use tutorial13::common::vboindexer::IndexedMesh;
use tutorial13::debug::lines::LineMode;
use tutorial13::debug::views::{ColorView, DebugVector, ShaderSwitches};
use tutorial13::frontends::headless::HeadlessRenderer;
use tutorial13::gl::Profile;
use tutorial13::pipeline::obj_parse::load_obj_threaded;
use tutorial13::scenes::cylinder::tutorial13::LIGHT_POS;
use tutorial13::scenes::cylinder::{self, Cylinder};

fn view(name: &str) -> ColorView {
    name.parse().unwrap()
}

fn with_view(renderer: &mut HeadlessRenderer, name: &str) -> RgbImage {
    renderer.scene_mut::<Cylinder>().switches.view = view(name);
    frame(renderer)
}

// Fails if a --view name does not round-trip, if V's list (`ColorView::CYCLE`) skips or repeats a
// view, or if choosing a vector drops the component C chose.
#[test]
fn view_names_round_trip_and_cycle() {
    for name in [
        "lit",
        "light",
        "light01",
        "eye.x",
        "eye01.z",
        "normal",
        "normal01.y",
    ] {
        assert_eq!(view(name).to_string(), name);
    }
    for bad in ["lit01", "lit.x", "light.w", "tangent", ""] {
        assert!(bad.parse::<ColorView>().is_err(), "{bad}");
    }
    let seen: Vec<String> = ColorView::CYCLE
        .iter()
        .map(|&(vector, mapped)| ColorView::default().with_vector(vector, mapped).to_string())
        .collect();
    assert_eq!(
        seen,
        ["lit", "light", "light01", "eye", "eye01", "normal", "normal01"]
    );
    let c = view("light01.y").with_vector(DebugVector::Eye, true);
    assert_eq!(c.to_string(), "eye01.y");
}

// Fails if NormalMappingDebug, with the tutorial's switches, computes anything other than the
// tutorial's NormalMapping shaders: the two programs must give the same frame, bit for bit.
#[test]
fn debug_program_with_tutorial_switches_equals_tutorial_program() {
    let test =
        "debug_program_with_tutorial_switches_equals_tutorial_program (the tutorial's files)";
    for assets in [Some(own_assets()), original_assets(test)]
        .into_iter()
        .flatten()
    {
        let mut renderer = renderer(&options(assets, Profile::Core));
        let tutorial = frame(&mut renderer);
        renderer.scene_mut::<Cylinder>().use_debug_program = true;
        let debug = frame(&mut renderer);
        assert_eq!(differing_pixels(&tutorial, &debug), 0);
    }
}

// Fails if the texture-normal view is not (n + 1) / 2 of the normal map: on a flat map (128, 128, 255)
// it must be (0.5, 0.5, 1.0) on every pixel of the cylinder, and its single components grey.
#[test]
fn texture_normal_view_of_a_flat_map() {
    let mut renderer = renderer(&options(flat_white_assets("views-normal"), Profile::Core));
    let mapped = with_view(&mut renderer, "normal01");
    let raw = with_view(&mut renderer, "normal");
    let z = with_view(&mut renderer, "normal01.z");
    let mut covered = 0;
    for (x, y, p) in mapped.enumerate_pixels() {
        if is_background(p) {
            continue;
        }
        covered += 1;
        for (c, expected) in p.0.iter().zip([128u8, 128, 255]) {
            assert!(c.abs_diff(expected) <= 1, "({x}, {y}): {:?}", p.0);
        }
        // Raw: n = (0.004, 0.004, 1.0).
        let r = raw.get_pixel(x, y).0;
        assert!(
            r[0] <= 2 && r[1] <= 2 && r[2] == 255,
            "raw ({x}, {y}): {r:?}"
        );
        assert_eq!(z.get_pixel(x, y).0, [255, 255, 255]);
    }
    assert!(covered > 100_000, "{covered}");
}

/// The tangent-space light (or eye) direction the vertex shader computes for mesh vertex `i`.
fn tangent_space(mesh: &IndexedMesh, i: usize, toward_light: bool) -> Vec3 {
    let v = Controls::default().view_matrix(); // M = identity
    let mv3 = Mat3::from_mat4(v);
    let p_cam = v.transform_point3(mesh.vertices[i]);
    let eye = -p_cam;
    let direction = if toward_light {
        v.transform_point3(LIGHT_POS) + eye
    } else {
        eye
    };
    let (t, b, n) = (
        mv3 * mesh.tangents[i],
        mv3 * mesh.bitangents[i],
        mv3 * mesh.normals[i],
    );
    Vec3::new(t.dot(direction), b.dot(direction), n.dot(direction))
}

// Fails if the light or eye view shows anything but normalize(TBNᵀ · direction) as the tutorial's
// vertex shader computes it: checked along the cylinder's front edge (world x = 0, z = 1), where the
// fragment interpolates between the edge's bottom and top vertices only (linearly in screen space,
// since both are at the same depth). Pixel centres lie up to half a pixel off the edge, which lets the
// third vertex weigh ~1.5 %: hence 4 levels of tolerance.
#[test]
fn light_and_eye_views_follow_their_formulas() {
    let mut renderer = renderer(&options(flat_white_assets("views-light"), Profile::Core));
    let mesh = renderer.scene_ref::<Cylinder>().tutorial.mesh.clone();
    let find = |target: Vec3| {
        (0..mesh.vertices.len())
            .find(|&i| (mesh.vertices[i] - target).length() < 1e-4)
            .expect("a vertex on the front edge")
    };
    let (bottom, top) = (
        find(Vec3::new(0.0, 0.0, 1.0)),
        find(Vec3::new(0.0, 2.0, 1.0)),
    );
    let (column, row_bottom) = project(Vec3::new(0.0, 0.0, 1.0));
    let (_, row_top) = project(Vec3::new(0.0, 2.0, 1.0));
    let x = column.floor() as u32;
    for (name, toward_light) in [("light01", true), ("eye01", false)] {
        let image = with_view(&mut renderer, name);
        let (a, b) = (
            tangent_space(&mesh, bottom, toward_light),
            tangent_space(&mesh, top, toward_light),
        );
        for y in [40u32, 120, 200, 300, 370] {
            let t = (y as f32 + 0.5 - row_bottom) / (row_top - row_bottom);
            let expected = (a.lerp(b, t).normalize() + 1.0) * 0.5 * 255.0;
            let got = image.get_pixel(x, y).0;
            for (g, e) in got.iter().zip(expected.to_array()) {
                assert!(
                    (*g as f32 - e).abs() <= 4.0,
                    "{name} at ({x}, {y}): {got:?}, expected {expected}"
                );
            }
        }
    }
}

// Fails if the specular switch does not swap the texture for the constant 0.3: with a white specular
// texture the two are the same colour (same frame); with the project's bricks (black mortar) they differ.
#[test]
fn specular_switch_is_texture_times_point_three_versus_constant() {
    let off = ShaderSwitches {
        specular_texture: false,
        ..Default::default()
    };
    let mut white = renderer(&options(flat_white_assets("views-specular"), Profile::Core));
    let with_texture = frame(&mut white);
    white.scene_mut::<Cylinder>().switches = off;
    assert!(frame_diff(&with_texture, &frame(&mut white)).max() <= 1);

    let mut bricks = renderer(&options(own_assets(), Profile::Core));
    let with_texture = frame(&mut bricks);
    bricks.scene_mut::<Cylinder>().switches = off;
    let without = frame(&mut bricks);
    let changed = differing_pixels(&with_texture, &without);
    println!("specular texture off changes {changed} pixels of the bricks");
    // Measured: 6930 (the lobe is narrow: exponent 5, 1/d² falloff).
    assert!(changed > 2_000);
}

// Fails if the switch does not reach the shader: the indexer's summed tangents are longer than 1, so
// normalizing the basis (the article's text) must change the lighting, without GL errors.
#[test]
fn normalized_tbn_switch_changes_the_lighting() {
    let mut renderer = renderer(&options(own_assets(), Profile::Core));
    let repository = frame(&mut renderer);
    renderer.scene_mut::<Cylinder>().switches.normalize_tbn = true;
    let article = frame(&mut renderer);
    let changed = differing_pixels(&repository, &article);
    println!("normalized TBN changes {changed} pixels");
    assert!(changed > 10_000);
}

/// A front-facing open cylinder whose U runs the tutorial's way on one half and mirrored on the other
/// (U = |angle − π| scaled), so that the handedness fix has something to fix on the mirrored half only.
fn mirrored_cylinder() -> String {
    let text = grid_cylinder_obj_text(32, 1, 1.0, 2.0, 3.7);
    let segments = 32.0;
    text.lines()
        .map(|line| match line.strip_prefix("vt ") {
            Some(rest) => {
                let mut it = rest.split_whitespace();
                let u: f32 = it.next().unwrap().parse().unwrap();
                let v = it.next().unwrap();
                // The generator's u = 3.7 (1 − s/32); fold it about the front (s = 16).
                let s = segments * (1.0 - u / 3.7);
                format!("vt {:.6} {v}", 3.7 * (s - 16.0).abs() / segments)
            }
            None => line.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

// Fails if turning the handedness fix off changes pixels where it flips no tangent, or changes
// nothing where it does. Which half it flips is read from the tangent basis itself (the tutorial's own
// layout, seen through the loader's negated V, is the half the fix flips); that half must change, the
// other must stay identical beyond the strip of triangles sharing the seam's vertices.
#[test]
fn handedness_switch_changes_only_the_mirrored_half() {
    let dir = scratch("views-mirrored");
    for file in ["diffuse.DDS", "normal.bmp", "specular.DDS"] {
        std::fs::copy(own_assets().join(file), dir.join(file)).unwrap();
    }
    std::fs::write(dir.join("cylinder.obj"), mirrored_cylinder()).unwrap();
    let no_fix = TangentOptions {
        handedness: false,
        ..Default::default()
    };
    // The corners the fix flips, by the side of the screen they are on.
    let soup = load_obj_threaded(&dir.join("cylinder.obj")).unwrap();
    let fixed_basis = compute_tangent_basis(&soup, TangentOptions::default());
    let raw_basis = compute_tangent_basis(&soup, no_fix);
    let flipped_x: Vec<f32> = (0..soup.vertices.len())
        .filter(|&i| fixed_basis.tangents[i] != raw_basis.tangents[i])
        .map(|i| soup.vertices[i].x)
        .collect();
    assert!(!flipped_x.is_empty());
    let flips_right = flipped_x.iter().all(|&x| x >= -1e-6);
    let flips_left = flipped_x.iter().all(|&x| x <= 1e-6);
    assert!(
        flips_right != flips_left,
        "the fix should act on one half only"
    );

    let mut renderer = renderer(&options(dir, Profile::Core));
    let fixed = frame(&mut renderer);
    assert!(
        renderer.host.scene.key('H').unwrap(),
        "H: the handedness fix"
    );
    let cylinder = renderer.scene_mut::<Cylinder>();
    assert_eq!(cylinder.mesh_options().tangents, no_fix);
    let unfixed = frame(&mut renderer);
    // Columns one segment either side of the seam (world x = 0).
    let segment = std::f32::consts::TAU / 32.0;
    let (left_edge, _) = project(Vec3::new(-segment.sin(), 0.0, segment.cos()));
    let (right_edge, _) = project(Vec3::new(segment.sin(), 0.0, segment.cos()));
    let (mut flipped_changed, mut flipped_total, mut other_changed) = (0u32, 0u32, 0u32);
    for (x, y, p) in fixed.enumerate_pixels() {
        if is_background(p) {
            continue;
        }
        let changed = u32::from(p != unfixed.get_pixel(x, y));
        let xc = x as f32 + 0.5;
        let (on_flipped, on_other) = if flips_right {
            (xc > right_edge + 1.0, xc < left_edge - 1.0)
        } else {
            (xc < left_edge - 1.0, xc > right_edge + 1.0)
        };
        if on_flipped {
            flipped_total += 1;
            flipped_changed += changed;
        } else if on_other {
            other_changed += changed;
        }
    }
    println!(
        "handedness off: {flipped_changed} of {flipped_total} pixels changed on the flipped half, \
         {other_changed} on the other"
    );
    assert_eq!(
        other_changed, 0,
        "pixels changed where the fix flips nothing"
    );
    assert!(
        flipped_changed * 2 > flipped_total,
        "{flipped_changed} of {flipped_total}"
    );
}

// Fails if any switch, in either profile, raises a GL error or leaves the frame unchanged when it
// should change it: every action is applied in turn (twice, so each ends where it started), with a
// frame after each, and `frame` asserts that GL reported nothing.
#[test]
fn every_switch_renders_without_gl_errors_in_both_profiles() {
    // Lighting switches first, while the lit view shows them; the normalized TBN after the mesh
    // switches (it hides the tangents' lengths, which normalizing before the sum changes); views last.
    // Lines, line mode, specular texture, normalize before sum, Gram-Schmidt, handedness,
    // normalized TBN, colour view, component.
    let actions = ['L', 'M', 'S', 'N', 'G', 'H', 'T', 'V', 'C'];
    for profile in [Profile::Core, Profile::Compat] {
        let mut renderer = renderer(&options(own_assets(), profile));
        let start = frame(&mut renderer);
        let mut previous = start.clone();
        for action in actions {
            assert!(renderer.host.scene.key(action).unwrap());
            let switched = frame(&mut renderer);
            let changed = differing_pixels(&previous, &switched);
            println!(
                "{profile:?} {action:?}: {changed} pixels changed; {}",
                renderer.host.scene.status()
            );
            // Both line paths draw the same pixels; every other action changes the frame.
            if action != 'M' {
                assert!(changed > 0, "{action:?} in {profile:?} changed nothing");
            }
            previous = switched;
        }
        // Undo: the cycles of NextView (7) and NextComponent (4) need more presses to come back.
        for action in actions {
            let presses = match action {
                'V' => ColorView::CYCLE.len() - 1,
                'C' => 3,
                _ => 1,
            };
            for _ in 0..presses {
                assert!(renderer.host.scene.key(action).unwrap());
            }
        }
        assert_eq!(
            differing_pixels(&start, &frame(&mut renderer)),
            0,
            "{profile:?}: not back to start"
        );
    }
}

// Fails if asking for the tutorial's immediate mode in a core context silently draws nothing or
// raises GL errors, instead of falling back to the line shader with a notice.
#[test]
fn legacy_lines_in_a_core_context_fall_back_with_a_notice() {
    let mut options = options(own_assets(), Profile::Core);
    options.scene.start(cylinder::LINES.to(true));
    options
        .scene
        .start(cylinder::LINE_MODE.to(LineMode::Legacy));
    let mut core = renderer(&options);
    assert_eq!(
        core.scene_mut::<Cylinder>().line_mode(),
        Some(LineMode::Shader)
    );
    let notice = core
        .scene_mut::<Cylinder>()
        .line_notice()
        .expect("a notice")
        .to_string();
    assert!(notice.contains("compatibility"), "{notice}");
    let with_lines = frame(&mut core);
    options.scene.start(cylinder::LINES.to(false));
    let without = frame(&mut renderer(&options));
    assert!(differing_pixels(&with_lines, &without) > 500);
    // In a compatibility context the same request draws in immediate mode, with the same pixels.
    options.scene.start(cylinder::LINES.to(true));
    options.profile = Profile::Compat;
    let mut compat = renderer(&options);
    assert_eq!(
        compat.scene_mut::<Cylinder>().line_mode(),
        Some(LineMode::Legacy)
    );
    assert!(compat.scene_mut::<Cylinder>().line_notice().is_none());
    assert_eq!(differing_pixels(&with_lines, &frame(&mut compat)), 0);
}
