//! An `--assets` folder that lacks some of a scene's files (docs/testing.md suggests one holding
//! just the tutorial's four): each missing file is taken from the crate's own assets/, with one notice per
//! scene load naming those files; a file that is there but broken stays an error naming it.

use std::path::{Path, PathBuf};

use image::RgbImage;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::scenes::{SceneDescriptor, SceneOptions, SCENES};

use crate::common;

/// Small frames: the comparisons are bit for bit, any size shows a different file.
const SIZE: (u32, u32) = (256, 192);

/// `scene`'s options on `assets` (`None`: the crate's own, as without `--assets`).
fn options(scene: &'static SceneDescriptor, assets: Option<PathBuf>) -> HeadlessOptions {
    HeadlessOptions {
        descriptor: scene,
        scene: SceneOptions {
            assets,
            ..Default::default()
        },
        width: SIZE.0,
        height: SIZE.1,
        ..Default::default()
    }
}

/// `scene`'s first frame, drawn from the crate's own assets.
fn crate_frame(scene: &'static SceneDescriptor) -> RgbImage {
    common::render(&options(scene, None))
}

/// The files `scene` reads from the assets folder: those `make-assets` writes for it.
fn files_of(scene: &SceneDescriptor) -> Vec<&'static str> {
    let files = (scene.generate_assets)().expect("the scene's generated files");
    files.into_iter().map(|(name, _)| name).collect()
}

/// How many times each of `scene`'s files in `dir` is among those taken from the crate so far.
fn times_taken(scene: &SceneDescriptor, dir: &Path) -> Vec<usize> {
    let taken = tutorial13::assets::taken_from_crate();
    files_of(scene)
        .iter()
        .map(|name| taken.iter().filter(|p| **p == dir.join(name)).count())
        .collect()
}

/// A folder as docs/testing.md suggests: the cylinder's four files alone, the look-alikes `make-assets`
/// writes (run as a user runs it), every other scene's folder deleted.
fn tutorials_four_files(name: &str) -> PathBuf {
    let dir = common::scratch(name);
    let out = common::run(
        common::tutorial13()
            .arg("make-assets")
            .arg("--out")
            .arg(&dir),
    );
    assert!(out.status.success(), "{}", common::text(&out.stderr));
    for scene in SCENES.iter().skip(1) {
        std::fs::remove_dir_all(dir.join(scene.name)).unwrap();
    }
    assert_eq!(
        common::files_under(&dir),
        ["cylinder.obj", "diffuse.DDS", "normal.bmp", "specular.DDS"].map(PathBuf::from)
    );
    dir
}

// Fails if a scene whose files an --assets folder lacks still stops (today: `sprite/diffuse.bmp: No
// such file or directory` for the sprite, cube and wall scenes on a folder holding the tutorial's
// four files), if it draws anything but the crate's files (one pixel differs), or if the notice is
// missing, is more than one line, or does not name each file taken from the crate. The cylinder,
// whose files are all there, must say nothing.
#[test]
fn the_tutorials_four_files_alone_run_every_scene_saying_what_came_from_the_crate() {
    let dir = tutorials_four_files("four_files");
    let scratch = common::scratch("four_files_shots");
    for scene in SCENES {
        let shot = scratch.join(format!("{}.png", scene.name));
        let out = common::run(
            common::tutorial13()
                .args(["--headless", "--size", "256x192", "--scene", scene.name])
                .arg("--assets")
                .arg(&dir)
                .arg("--screenshot")
                .arg(&shot),
        );
        let stderr = common::text(&out.stderr);
        assert!(out.status.success(), "{scene}: {stderr}");
        let notices: Vec<&str> = stderr.lines().filter(|l| l.contains("has no")).collect();
        if scene.name == "cylinder" {
            assert!(notices.is_empty(), "{scene}: {stderr}");
            continue;
        }
        assert_eq!(notices.len(), 1, "{scene}: {stderr}");
        for name in files_of(scene) {
            assert!(notices[0].contains(name), "{scene}: {name}: {stderr}");
        }
        assert!(
            notices[0].contains(&common::own_assets().display().to_string()),
            "{scene}: the notice does not say where the files came from: {stderr}"
        );
        let frame = image::open(&shot).unwrap().into_rgb8();
        let differ = common::differing_pixels(&frame, &crate_frame(scene));
        assert_eq!(differ, 0, "{scene}: {differ} pixels differ");
    }
}

// Fails if the window's Enter cannot step from the cylinder on a folder of the tutorial's four files
// through every scene and round again (each switch must draw the scene from the crate's files, bit
// for bit), or if the files taken from the crate are not recorded (the notice names each of them), or
// are noticed again on the second round. `switch_scene` is the headless Enter: it builds the next scene
// through its descriptor's `build` (`SceneType::new` → `SceneOptions::asset_files`), as the window's
// `Renderer::switch_scene` does.
#[test]
fn enter_steps_through_every_scene_from_the_tutorials_four_files() {
    let dir = tutorials_four_files("enter");
    let crate_frames: Vec<RgbImage> = SCENES.iter().map(|s| crate_frame(s)).collect();
    let mut renderer = common::renderer(&options(SCENES[0], Some(dir.clone())));
    common::frame(&mut renderer);
    for round in 0..2 {
        for i in (1..=SCENES.len()).map(|i| i % SCENES.len()) {
            let scene = SCENES[i];
            renderer.host.switch_scene(scene).unwrap();
            let frame = common::frame(&mut renderer);
            let from_crate = usize::from(scene.name != "cylinder");
            assert_eq!(
                times_taken(scene, &dir),
                vec![from_crate; files_of(scene).len()],
                "round {round}: {scene}"
            );
            if from_crate == 1 {
                let differ = common::differing_pixels(&frame, &crate_frames[i]);
                assert_eq!(differ, 0, "round {round}: {scene}: {differ} pixels differ");
            }
        }
    }
}

// Fails if a scene on an empty --assets folder stops, draws one pixel other than from the crate's own
// files, or does not record (and so name in its notice) every file it took from the crate. Replaces
// the tests that a missing map is an error: it is now taken from the crate.
#[test]
fn an_empty_assets_folder_draws_the_crates_files() {
    for scene in SCENES {
        let dir = common::scratch(&format!("empty_{}", scene.name));
        let frame = common::render(&options(scene, Some(dir.clone())));
        let differ = common::differing_pixels(&frame, &crate_frame(scene));
        assert_eq!(differ, 0, "{scene}: {differ} pixels differ");
        assert_eq!(
            times_taken(scene, &dir),
            vec![1; files_of(scene).len()],
            "{scene}"
        );
    }
}

// Fails if a file that is in the --assets folder but cut short is replaced by the crate's copy (the
// learner would look at the crate's file and never learn that theirs is broken), panics, or is
// reported in more than one line or without naming the file in the folder. Every file of every scene
// is cut short in turn, the others left whole.
#[test]
fn a_broken_file_in_the_assets_folder_is_an_error_naming_it() {
    for scene in SCENES {
        for name in files_of(scene) {
            let dir = common::scratch(&format!("broken_{}", scene.name));
            let broken = dir.join(name);
            std::fs::create_dir_all(broken.parent().unwrap()).unwrap();
            let bytes = std::fs::read(common::own_assets().join(name)).unwrap();
            std::fs::write(&broken, &bytes[..bytes.len() / 2]).unwrap();
            let error = match HeadlessRenderer::new(&options(scene, Some(dir.clone()))) {
                Ok(_) => panic!("{scene}: built with half of {name}"),
                Err(e) => e,
            };
            let message = error.to_string();
            println!("{message}");
            assert_eq!(error.path(), Some(broken.as_path()), "{message}");
            assert!(
                message.contains(&broken.display().to_string()) && !message.contains('\n'),
                "{message}"
            );
        }
    }
}

// Fails if a file missing from both the --assets folder and the crate's own is not an error, or if
// the error names the crate's copy rather than the file the user asked for, or does not say that
// the crate's copy is missing too.
#[test]
fn a_file_missing_from_the_crate_too_names_the_one_asked_for() {
    let dir = common::scratch("missing_both");
    let no_crate = common::scratch("missing_both_crate");
    let names = ["sprite/diffuse.bmp", "sprite/normal.bmp"];
    let error = tutorial13::assets::find_assets(&dir, &no_crate, names).unwrap_err();
    let message = error.to_string();
    println!("{message}");
    assert_eq!(error.path(), Some(dir.join(names[0]).as_path()));
    assert!(
        message.contains(&no_crate.join(names[0]).display().to_string())
            && message.contains("missing too"),
        "{message}"
    );

    // With the crate's copy there, the folder's missing file is found in the crate and listed.
    std::fs::create_dir_all(no_crate.join("sprite")).unwrap();
    std::fs::write(no_crate.join(names[0]), "x").unwrap();
    std::fs::create_dir_all(dir.join("sprite")).unwrap();
    std::fs::write(dir.join(names[1]), "y").unwrap();
    let found = tutorial13::assets::find_assets(&dir, &no_crate, names).unwrap();
    assert_eq!(found.paths, [no_crate.join(names[0]), dir.join(names[1])]);
    assert_eq!(found.missing, [dir.join(names[0])]);
}

// Fails if a scene's `asset_files` (what the browser page fetches for it) are not the files
// `make-assets` writes for it, in that order.
#[test]
fn each_scenes_asset_files_are_those_it_generates() {
    for scene in tutorial13::scenes::SCENES {
        assert_eq!(scene.asset_files, files_of(scene), "{}", scene.name);
    }
}
