//! Live shader editing (the window reloads a shader file when it is saved, or on F5): headless, the
//! same reload between two frames. A learner's edit shows in the next frame; a shader that does not
//! compile is reported with its file and the driver's log, and the last good programs keep drawing.

use crate::common;

use std::path::Path;

use crate::common::{frame, own_assets, pixel_diff, renderer, scratch};
use image::RgbImage;
use tutorial13::common::shader::crate_shader_dir;
use tutorial13::gl::Profile;
use tutorial13::scenes::cylinder::Cylinder;
use tutorial13::scenes::Scene;

const FRAGMENT: &str = "NormalMapping.fragmentshader";

/// The crate's shaders copied into a folder of the test's own, and a renderer reading them from it.
fn renderer_on_copied_shaders(
    name: &str,
) -> (
    tutorial13::frontends::headless::HeadlessRenderer,
    std::path::PathBuf,
) {
    let dir = scratch(name);
    for entry in std::fs::read_dir(crate_shader_dir()).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, dir.join(path.file_name().unwrap())).unwrap();
    }
    let mut options = common::options(own_assets(), Profile::Core);
    options.scene.shaders = Some(dir.clone());
    (renderer(&options), dir)
}

fn mean_brightness(image: &RgbImage) -> f64 {
    let sum: u64 = image
        .pixels()
        .map(|p| p.0.iter().map(|&c| u64::from(c)).sum::<u64>())
        .sum();
    sum as f64 / (image.width() * image.height() * 3) as f64
}

fn write(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

// Fails if a reload does not read the edited file (the next frame is unchanged or not darker), if a
// broken file is accepted, not named, or reported without the driver's log, if it changes the frame
// (the last good program must keep drawing), or if saving the original back does not restore the
// first frame bit for bit.
#[test]
fn saved_shader_shows_in_the_next_frame_and_a_broken_one_changes_nothing() {
    let (mut r, dir) = renderer_on_copied_shaders("edit");
    let first = frame(&mut r);
    let fragment = dir.join(FRAGMENT);
    let good = std::fs::read_to_string(&fragment).unwrap();

    // A learner's edit: the lit colour at half strength.
    let last_brace = good.rfind('}').expect("a closing brace");
    let halved = format!("{}    color *= 0.5;\n}}\n", &good[..last_brace]);
    write(&fragment, &halved);
    r.host.reload_shaders().expect("the edited shader compiles");
    let edited = frame(&mut r);
    let (differing, _, _) = pixel_diff(&first, &edited);
    let (before, after) = (mean_brightness(&first), mean_brightness(&edited));
    println!("edit: {differing} pixels changed, mean brightness {before:.2} -> {after:.2}");
    assert!(differing > 10_000, "only {differing} pixels changed");
    assert!(after < before, "{after} >= {before}");

    // A typo: the error names the file and carries the driver's log; the frame stays the edited one.
    write(&fragment, &halved.replace("color *= 0.5;", "color *= 0.5"));
    let error = r
        .host
        .reload_shaders()
        .expect_err("a shader with a syntax error")
        .to_string();
    println!("broken: {error}");
    assert!(error.contains(&fragment.display().to_string()), "{error}");
    assert!(error.contains("compilation failed"), "{error}");
    assert!(
        error.to_lowercase().contains("error"),
        "no driver log: {error}"
    );
    let still = frame(&mut r);
    assert!(still == edited, "a broken shader changed the frame");

    // Saved back as it was: the first frame again, bit for bit.
    write(&fragment, &good);
    r.host.reload_shaders().expect("the original compiles");
    assert!(
        frame(&mut r) == first,
        "the original shader does not give the first frame back"
    );
}

// Fails if the line shader or the debugging program are not reloaded too, or if a failure in one
// program lets the others change (a reload is all or nothing).
#[test]
fn every_program_reloads_and_a_failure_keeps_them_all() {
    let (mut r, dir) = renderer_on_copied_shaders("all");
    {
        let scene = r.scene_mut::<Cylinder>();
        scene.set_show_lines(true).unwrap();
        let files = scene.shader_files();
        assert_eq!(files.len(), 8, "{files:?}");
        assert!(files.iter().all(|f| f.starts_with(&dir)), "{files:?}");
    }
    let with_lines = frame(&mut r);

    // Lines drawn in yellow instead of their own colours.
    let lines_fragment = dir.join("DebugLines.fragmentshader");
    let good_lines = std::fs::read_to_string(&lines_fragment).unwrap();
    let end = good_lines.rfind('}').unwrap();
    write(
        &lines_fragment,
        &format!(
            "{}    color = vec4(1.0, 1.0, 0.0, 1.0);\n}}\n",
            &good_lines[..end]
        ),
    );
    r.host
        .reload_shaders()
        .expect("the edited line shader compiles");
    let yellow = frame(&mut r);
    let yellow_pixels = yellow.pixels().filter(|p| p.0 == [255, 255, 0]).count();
    assert!(
        yellow_pixels > 500,
        "{yellow_pixels} yellow pixels: the line shader was not reloaded"
    );

    // A broken tutorial shader: nothing changes, the yellow lines included.
    let fragment = dir.join(FRAGMENT);
    write(&fragment, "#version 330 core\nvoid main() { nonsense }\n");
    write(&lines_fragment, &good_lines);
    assert!(r.host.reload_shaders().is_err());
    assert!(
        frame(&mut r) == yellow,
        "a failed reload changed some program"
    );

    // Both good again: the frame with the lines as first drawn.
    write(
        &fragment,
        &std::fs::read_to_string(crate_shader_dir().join(FRAGMENT)).unwrap(),
    );
    r.host.reload_shaders().unwrap();
    assert!(frame(&mut r) == with_lines);
}

// Fails if a uniform the shaders no longer declare (a learner renames `MV3x3` to `MV3X3` in both
// files) loads anyway and draws with a matrix that is never set, if the error does not name
// the file and the missing name, or if the refused reload changes the frame; and if a declared
// uniform the shader merely stops using (removed by the compiler) is refused.
#[test]
fn a_misspelt_uniform_is_refused_and_an_unused_one_is_not() {
    let (mut r, dir) = renderer_on_copied_shaders("uniform-typo");
    let first = frame(&mut r);
    let vertex = dir.join("NormalMapping.vertexshader");
    let fragment = dir.join(FRAGMENT);
    let good = std::fs::read_to_string(&vertex).unwrap();
    let good_fragment = std::fs::read_to_string(&fragment).unwrap();
    assert!(good.contains("MV3x3"), "the vertex shader uses MV3x3");
    write(&vertex, &good.replace("MV3x3", "MV3X3"));
    write(&fragment, &good_fragment.replace("MV3x3", "MV3X3"));
    let error = r
        .host
        .reload_shaders()
        .expect_err("a misspelt uniform is refused");
    let message = error.to_string();
    assert!(
        message.contains("NormalMapping.vertexshader") && message.contains("'MV3x3'"),
        "{message}"
    );
    assert!(frame(&mut r) == first, "a refused reload changed the frame");
    write(&fragment, &good_fragment);

    // Declared, no longer used: the light's position is declared and ignored (the light is put at
    // the camera), so the compiler drops it, and the program must still load and draw.
    let at_camera = good.replace("(V * vec4(LightPosition_worldspace, 1.0)).xyz", "vec3(0.0)");
    assert_ne!(at_camera, good, "the edit found its line");
    write(&vertex, &at_camera);
    r.host
        .reload_shaders()
        .expect("a declared but unused uniform is not an error");
    assert!(frame(&mut r) != first, "the edit did not show");
}

// Fails if the reading of `uniform` declarations misses a name or invents one: comments (one that
// ends right before `uniform`, an empty one), several names in one declaration, arrays, precision
// and layout qualifiers, and a uniform block (not listed).
#[test]
fn declared_uniforms_are_read_from_the_source() {
    let source = "#version 330 core\n\
        // uniform mat4 Commented;\n\
        /* uniform vec3 Blocked; */\n\
        uniform mat4 MVP;\n\
        uniform highp float A, B[2];\n\
        layout(location = 3) uniform vec3 Light = vec3(0);\n\
        in vec3 uniformish;\n\
        /* no space after a comment */uniform float C;/**/\n\
        uniform Lights { vec3 colour; };\n\
        void main() { gl_Position = MVP * vec4(A); }\n";
    assert_eq!(
        tutorial13::common::shader::declared_uniforms(source),
        ["MVP", "A", "B", "Light", "C"]
    );
}

// Fails if a --shaders folder holding only some of a scene's files does not take the rest from the
// crate's shaders/ (the frame would differ or the run fail), or if the log does not say which file
// that was: the line names the vertex shader, missing from the folder, and not the fragment
// shader, which is there. Also fails if an empty link log is logged at the debug level.
#[test]
fn a_partial_shaders_folder_takes_the_rest_from_the_crate_and_says_which() {
    let dir = scratch("partial-shaders");
    let shaders = dir.join("mine");
    std::fs::create_dir_all(&shaders).unwrap();
    std::fs::copy(crate_shader_dir().join(FRAGMENT), shaders.join(FRAGMENT)).unwrap();
    let out = common::run(
        common::tutorial13()
            .args([
                "--headless",
                "--screenshot",
                "partial.png",
                "--shaders",
                "mine",
            ])
            .env("RUST_LOG", "tutorial13=debug")
            .current_dir(&dir),
    );
    let stderr = common::text(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let said = |name: &str| stderr.contains(&format!("{name} is not in the --shaders folder"));
    assert!(said("NormalMapping.vertexshader"), "{stderr}");
    assert!(!said(FRAGMENT), "{stderr}");
    // llvmpipe links these programs without a word: an empty link log is not logged.
    assert!(stderr.contains("DEBUG"), "{stderr}");
    assert!(!stderr.contains("link log:"), "{stderr}");
    let partial = image::open(dir.join("partial.png")).unwrap().into_rgb8();
    let whole = common::headless_screenshot(&dir, "whole.png", &[]);
    assert!(partial == whole, "the partial folder changed the frame");
}

// Fails if a linked program is not deleted with its value (GL would keep it, and a learner's every
// reload would leak one), if its uniforms are not found by name, or if the names its two files
// declare are not listed (the vertex shader's first, then the fragment shader's).
#[test]
fn a_program_finds_its_uniforms_and_is_deleted_with_its_value() {
    use glow::HasContext;
    use tutorial13::common::shader::load_program;
    use tutorial13::gl::context::HeadlessContext;

    let context = HeadlessContext::new(Profile::Core, false).expect("a core context on llvmpipe");
    let gl = context.gl();
    let program = load_program(gl, "NormalMapping.vertexshader", FRAGMENT, None).unwrap();
    let id = program.id;
    // SAFETY: a query on the current context.
    assert!(unsafe { gl.is_program(id) });
    assert!(program.uniform("MVP").is_some());
    assert!(program.uniform("NoSuchUniform").is_none());
    assert_eq!(
        program.declared_uniforms,
        [
            "MVP",
            "V",
            "M",
            "MV3x3",
            "LightPosition_worldspace",
            "DiffuseTextureSampler",
            "NormalTextureSampler",
            "SpecularTextureSampler",
            "V",
            "M",
            "MV3x3",
            "LightPosition_worldspace"
        ]
    );
    drop(program);
    // SAFETY: as above.
    assert!(
        !unsafe { gl.is_program(id) },
        "the program outlived its value"
    );
}
