//! Helpers shared by the test modules: headless set-up, asset folders (the project's, the
//! tutorial's or skipped), scratch folders, golden images, projection to pixels, a private Xvfb.
#![allow(dead_code)] // a helper no test calls any more is not an error

pub mod xvfb;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use glam::Vec3;
use image::{Rgb, RgbImage, RgbaImage};
use proptest::test_runner::TestCaseError;
use tutorial13::assets::{encode_bmp, encode_dds_dxt3};
use tutorial13::common::controls::Controls;
use tutorial13::common::objloader::TriangleSoup;
use tutorial13::common::tangentspace::TangentBasis;
use tutorial13::common::vboindexer::{self, IndexOptions, IndexedMesh};
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::gl::{ContextInfo, Profile};
use tutorial13::pipeline::indexer::{index_vbo_hashed, index_vbo_tbn_hashed};
use tutorial13::scenes::cylinder::CylinderFiles;
use tutorial13::scenes::SceneOptions;

pub const W: u32 = 1024;
pub const H: u32 = 768;
pub const BACKGROUND: [u8; 3] = [0, 0, 102];

pub fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

pub fn own_assets() -> PathBuf {
    manifest().join("assets")
}

/// Says on the terminal (not in the captured test output, so it shows in a passing `cargo test`)
/// that `test`, or a part of it, is skipped and why.
pub fn skip(test: &str, reason: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipped: {test}: {reason}");
}

/// Every file of the tutorial's folder that a test reads (.ci/run checks the same list).
pub const ORIGINAL_FILES: [&str; 10] = [
    "cylinder.obj",
    "cylinder.mtl",
    "diffuse.DDS",
    "specular.DDS",
    "normal.bmp",
    "ref.png",
    "cpp-llvmpipe-core.png",
    "cpp-llvmpipe-compat-lines.png",
    "cpp-llvmpipe-core-msaa4.png",
    "cpp-llvmpipe-compat-lines-msaa4.png",
];

/// The tutorial's own files (cylinder.obj, the DDS and BMP maps, ref.png and the C++ original's
/// frames): the folder named by `TUTORIAL13_ORIGINAL_ASSETS`, else `../shared/tutorial13-original`
/// beside the crate. The project never copies them in, so a plain clone has neither: then `test`
/// says it is skipped and gets `None`, unless `TUTORIAL13_REQUIRE_ORIGINAL=1` (set by .ci/run), which
/// fails instead so that CI never skips.
pub fn original_assets(test: &str) -> Option<PathBuf> {
    let dir = match std::env::var_os("TUTORIAL13_ORIGINAL_ASSETS") {
        Some(dir) => PathBuf::from(dir),
        None => manifest().join("../shared/tutorial13-original"),
    };
    let missing: Vec<&str> = ORIGINAL_FILES
        .into_iter()
        .filter(|name| !dir.join(name).is_file())
        .collect();
    if missing.is_empty() {
        return Some(dir);
    }
    let reason = format!(
        "the tutorial's own files are not in {} ({} missing; set TUTORIAL13_ORIGINAL_ASSETS=DIR \
         to a folder holding them)",
        dir.display(),
        missing.join(", ")
    );
    assert!(
        std::env::var_os("TUTORIAL13_REQUIRE_ORIGINAL").is_none(),
        "TUTORIAL13_REQUIRE_ORIGINAL is set but {reason}"
    );
    skip(test, &reason);
    None
}

/// The renderer the bit-for-bit comparisons were measured on (the C++ original's frames in
/// ../shared/tutorial13-original were taken on it): GL_RENDERER and GL_VERSION must contain these.
pub const REFERENCE_RENDERER: &str = "llvmpipe (LLVM 15.0.6";
pub const REFERENCE_MESA: &str = "Mesa 22.3.6";

/// `None` on the reference renderer; otherwise why a bit-for-bit comparison does not apply here
/// (rasterization and float rounding are only known to agree on the Mesa and LLVM they were measured on).
pub fn not_reference_renderer(info: &ContextInfo) -> Option<String> {
    if info.renderer.contains(REFERENCE_RENDERER) && info.version_string.contains(REFERENCE_MESA) {
        None
    } else {
        Some(format!(
            "this is {} with GL_VERSION {:?}; the frames are known to agree bit for bit only on \
             {REFERENCE_RENDERER}, …) from {REFERENCE_MESA}",
            info.renderer, info.version_string
        ))
    }
}

/// Whether `test`'s bit-for-bit comparison applies to the renderer of `info`; where it does not, says
/// it is skipped and why, unless `TUTORIAL13_REQUIRE_REFERENCE_RENDERER=1` (set by .ci/run, whose
/// machine is the reference), which fails instead.
pub fn on_reference_renderer(test: &str, info: &ContextInfo) -> bool {
    match not_reference_renderer(info) {
        None => true,
        Some(reason) => {
            skip_off_reference(test, &reason);
            false
        }
    }
}

/// [`on_reference_renderer`] for this machine's headless renderer, for the tests whose frames come
/// from other processes (the window under Xvfb and the headless binary: both use the same Mesa here).
pub fn reference_renderer_here(test: &str) -> bool {
    let context = tutorial13::gl::context::HeadlessContext::new(Profile::Core, false)
        .expect("a headless context, to ask which renderer this is");
    on_reference_renderer(test, context.info())
}

/// Says that `test`'s bit-for-bit comparison is skipped for `reason` (not the reference renderer),
/// or fails where `TUTORIAL13_REQUIRE_REFERENCE_RENDERER=1`.
pub fn skip_off_reference(test: &str, reason: &str) {
    assert!(
        std::env::var_os("TUTORIAL13_REQUIRE_REFERENCE_RENDERER").is_none(),
        "TUTORIAL13_REQUIRE_REFERENCE_RENDERER is set but {reason}"
    );
    skip(test, reason);
}

/// An inclusive rectangle of pixels: (x0, y0, x1, y1).
pub type PixelRect = (u32, u32, u32, u32);

/// How two frames of one size differ, pixel by pixel; a pixel differs by its largest channel
/// difference.
pub struct FrameDiff {
    /// How many pixels differ by each amount: `by_amount[0]` is the number of equal pixels.
    by_amount: [usize; 256],
    /// The rectangle that holds every differing pixel.
    pub bbox: Option<PixelRect>,
    /// Every channel's difference, summed over the frame.
    pub total: u64,
}

impl FrameDiff {
    /// How many pixels were compared.
    pub fn pixels(&self) -> usize {
        self.by_amount.iter().sum()
    }

    /// How many pixels differ at all.
    pub fn differing(&self) -> usize {
        self.over(0)
    }

    /// How many pixels differ by more than `tolerance`.
    pub fn over(&self, tolerance: u8) -> usize {
        self.by_amount[usize::from(tolerance) + 1..].iter().sum()
    }

    /// The largest channel difference (0 for equal frames).
    pub fn max(&self) -> u8 {
        self.by_amount.iter().rposition(|&n| n > 0).unwrap_or(0) as u8
    }
}

/// How `a` and `b`, frames of the same size, differ.
pub fn frame_diff(a: &RgbImage, b: &RgbImage) -> FrameDiff {
    assert_eq!(a.dimensions(), b.dimensions(), "frames of different sizes");
    let mut d = FrameDiff {
        by_amount: [0; 256],
        bbox: None,
        total: 0,
    };
    for ((x, y, p), q) in a.enumerate_pixels().zip(b.pixels()) {
        let channels = [0, 1, 2].map(|c| p[c].abs_diff(q[c]));
        let m = channels.into_iter().max().unwrap();
        d.by_amount[usize::from(m)] += 1;
        d.total += channels.into_iter().map(u64::from).sum::<u64>();
        if m > 0 {
            d.bbox = Some(match d.bbox {
                None => (x, y, x, y),
                Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
            });
        }
    }
    d
}

/// How many pixels differ, the largest channel difference, and the rectangle that holds every
/// differing pixel.
pub fn pixel_diff(a: &RgbImage, b: &RgbImage) -> (usize, u8, Option<PixelRect>) {
    let d = frame_diff(a, b);
    (d.differing(), d.max(), d.bbox)
}

/// How many pixels differ between `a` and `b`.
pub fn differing_pixels(a: &RgbImage, b: &RgbImage) -> usize {
    frame_diff(a, b).differing()
}

/// How many pixels of `image` are not the background.
pub fn drawn_pixels(image: &RgbImage) -> usize {
    image.pixels().filter(|p| !is_background(p)).count()
}

/// Pixels differing, the largest channel difference, and the mean channel difference over the
/// pixels `a` draws (not over the whole frame, so that the background does not dilute it).
pub fn compare_drawn(a: &RgbImage, b: &RgbImage) -> (usize, u8, f64) {
    let d = frame_diff(a, b);
    let drawn = drawn_pixels(a);
    assert!(drawn > 0, "nothing drawn to take a mean difference over");
    (d.differing(), d.max(), d.total as f64 / (drawn * 3) as f64)
}

pub fn options(assets: PathBuf, profile: Profile) -> HeadlessOptions {
    HeadlessOptions {
        scene: SceneOptions {
            assets: Some(assets),
            ..Default::default()
        },
        width: W,
        height: H,
        profile,
        ..Default::default()
    }
}

pub fn renderer(options: &HeadlessOptions) -> HeadlessRenderer {
    HeadlessRenderer::new(options).expect("headless renderer")
}

/// The cylinder scene's files in `options` (the scene [`options`] draws): `--model` and the maps.
pub fn cylinder_files(options: &mut HeadlessOptions) -> &mut CylinderFiles {
    options.scene.get_mut::<CylinderFiles>()
}

/// A core-profile renderer of the cylinder scene on `assets`, its options changed by `set` first
/// (its controls started through their typed handles: `|o| { o.start(LINES.to(true)); }`).
pub fn cylinder_renderer(assets: PathBuf, set: impl FnOnce(&mut SceneOptions)) -> HeadlessRenderer {
    let mut options = options(assets, Profile::Core);
    set(&mut options.scene);
    renderer(&options)
}

/// The first frame of [`cylinder_renderer`].
pub fn cylinder_frame(assets: PathBuf, set: impl FnOnce(&mut SceneOptions)) -> RgbImage {
    frame(&mut cylinder_renderer(assets, set))
}

/// One frame (time frozen at 0), alpha dropped as in a screenshot. `render_frames` fails on any GL
/// error, so every frame taken through here is also checked free of GL errors.
pub fn frame(renderer: &mut HeadlessRenderer) -> RgbImage {
    rgb(renderer
        .render_frames(1)
        .expect("a frame without GL errors"))
}

pub fn render(options: &HeadlessOptions) -> RgbImage {
    frame(&mut renderer(options))
}

pub fn rgb(frame: RgbaImage) -> RgbImage {
    image::DynamicImage::ImageRgba8(frame).into_rgb8()
}

pub fn is_background(p: &Rgb<u8>) -> bool {
    p.0 == BACKGROUND
}

/// A fresh, empty folder for one test: target/tmp/<test file>-<name>, the file being the caller's (the
/// tests share one binary, so two files may use the same name). Emptied when the test starts, kept
/// after it ends so that a failure's files can be looked at.
#[track_caller]
pub fn scratch(name: &str) -> PathBuf {
    let caller = Path::new(std::panic::Location::caller().file());
    let file = caller
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("test");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{file}-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("create {}: {e}", dir.display()));
    dir
}

/// Every file under `dir`, in any folder depth, as paths relative to it.
pub fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                folders.push(path);
            } else {
                files.push(path.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    files.sort();
    files
}

/// A debug build on two busy cores renders in well under a second; this only catches hangs.
const RUN_TIMEOUT: Duration = Duration::from_secs(300);

/// The binary with a predictable environment: no RUST_LOG, so stderr holds only what it always
/// prints, and no stdin.
pub fn tutorial13() -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_tutorial13"));
    cmd.env_remove("RUST_LOG").stdin(Stdio::null());
    cmd
}

/// Runs to completion (killed and failed after [`RUN_TIMEOUT`]), capturing stdout and stderr.
pub fn run(cmd: &mut Command) -> Output {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {cmd:?}: {e}"));
    let stdout = drain(child.stdout.take());
    let stderr = drain(child.stderr.take());
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for the child") {
            break status;
        }
        if start.elapsed() > RUN_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            let err = text(&stderr.join().unwrap());
            panic!("{cmd:?} still running after {RUN_TIMEOUT:?}; killed. stderr:\n{err}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Output {
        status,
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    }
}

/// Reads a child's pipe to its end on a thread, so that a chatty child never blocks on a full pipe.
fn drain<R: Read + Send + 'static>(pipe: Option<R>) -> std::thread::JoinHandle<Vec<u8>> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        if let Some(mut pipe) = pipe {
            let _ = pipe.read_to_end(&mut bytes);
        }
        bytes
    })
}

/// A run's output as text (invalid UTF-8 replaced).
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The binary's headless frame (`--headless --screenshot NAME` plus `args`), run in `dir`.
pub fn headless_screenshot(dir: &Path, name: &str, args: &[&str]) -> RgbImage {
    let out = run(tutorial13()
        .args(["--headless", "--screenshot", name])
        .args(args)
        .current_dir(dir));
    assert!(out.status.success(), "{}", text(&out.stderr));
    image::open(dir.join(name)).unwrap().into_rgb8()
}

/// Where a failing image test leaves its frame and difference map: target/test-output/.
pub fn output_dir() -> PathBuf {
    let out = manifest().join("target/test-output");
    std::fs::create_dir_all(&out).unwrap();
    out
}

/// image-compare's hybrid score (SSIM on luma, RMS on chroma; 1 = identical) of `frame` against
/// `reference`. Below `min`, `frame` and the difference map are written to [`output_dir`] as
/// `<name>.png` and `<name>.diff.png`.
pub fn hybrid_score(reference: &RgbImage, frame: &RgbImage, name: &str, min: f64) -> f64 {
    let result = image_compare::rgb_hybrid_compare(reference, frame).expect("same size");
    if result.score < min {
        let out = output_dir();
        frame.save(out.join(format!("{name}.png"))).unwrap();
        let map = out.join(format!("{name}.diff.png"));
        result.image.to_color_map().save(&map).unwrap();
        eprintln!(
            "{name}: score {:.5} < {min}; frame and difference map in {}",
            result.score,
            out.display()
        );
    }
    result.score
}

/// The bar for a golden image off the reference renderer, where the frame is lit ([`LitDifference`]):
/// image-compare's hybrid score over the golden's lit rectangle (SSIM on luma, RMS on chroma: the
/// shapes; it barely sees a change of brightness, a golden 3 % dimmer scores 0.998 to 0.999) ...
pub const GOLDEN_MIN_LIT_SCORE: f64 = 0.98;
/// ... and how far the lit pixels' mean level moved ([`LitDifference::shift`]): a golden 3 % dimmer
/// or brighter moves it by 2.7 to 4.3 % (the five goldens), and fails.
pub const GOLDEN_MAX_SHIFT: f64 = 0.015;

/// Compares `frame` with the committed golden image tests/golden/`name`.png: bit for bit on the
/// reference renderer (its frames are deterministic), else by [`GOLDEN_MIN_LIT_SCORE`] and
/// [`GOLDEN_MAX_SHIFT`] over the lit rectangle. Also checks that the bar is a bar: the golden 3 % dimmer where it is lit fails it. Writes
/// the golden instead when `TUTORIAL13_UPDATE_GOLDEN=1` (then look at it before committing).
pub fn assert_matches_golden(frame: &RgbImage, name: &str) {
    let path = manifest().join("tests/golden").join(format!("{name}.png"));
    if std::env::var_os("TUTORIAL13_UPDATE_GOLDEN").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        frame.save(&path).unwrap();
        return;
    }
    let golden = image::open(&path)
        .unwrap_or_else(|e| {
            panic!(
                "{}: {e} (TUTORIAL13_UPDATE_GOLDEN=1 writes it)",
                path.display()
            )
        })
        .into_rgb8();
    assert_eq!(golden.dimensions(), frame.dimensions(), "{name}: size");
    for factor in [0.97, 1.03] {
        let changed = lit_difference(&golden, &dim_lit(&golden, factor));
        println!("{name}: the golden × {factor} where lit: {changed}");
        assert!(
            !changed.passes(),
            "{name}: × {factor} passes the bar ({changed})"
        );
    }
    let context = tutorial13::gl::context::HeadlessContext::new(Profile::Core, false)
        .expect("a headless context, to ask which renderer this is");
    if not_reference_renderer(context.info()).is_none() {
        let (differing, max, bbox) = pixel_diff(&golden, frame);
        if differing > 0 {
            frame
                .save(output_dir().join(format!("{name}.png")))
                .unwrap();
        }
        assert!(
            differing == 0,
            "{name}: {differing} pixels differ from the golden, by up to {max} levels, within \
             {bbox:?}, where the reference renderer draws it bit for bit (frame in {})",
            output_dir().display()
        );
        return;
    }
    let difference = lit_difference(&golden, frame);
    println!("{name}: {difference}");
    if !difference.passes() {
        frame
            .save(output_dir().join(format!("{name}.png")))
            .unwrap();
    }
    assert!(
        difference.passes(),
        "{name}: {difference}; the bar: a score of at least {GOLDEN_MIN_LIT_SCORE}, the lit \
         level moved by at most {:.1} % (frame in {})",
        GOLDEN_MAX_SHIFT * 100.0,
        output_dir().display()
    );
}

/// How `frame` differs from `golden` where either is lit (not the background, the colour of the
/// golden's top-left pixel).
#[derive(Debug, Clone, Copy)]
pub struct LitDifference {
    /// image-compare's hybrid score over the golden's lit rectangle ([`lit_score`]).
    pub score: f64,
    /// How far the lit pixels' mean level moved (the channel that moved most), as a fraction of
    /// their mean level: brighter, dimmer or another tint.
    pub shift: f64,
}

impl LitDifference {
    pub fn passes(&self) -> bool {
        self.score >= GOLDEN_MIN_LIT_SCORE && self.shift <= GOLDEN_MAX_SHIFT
    }
}

impl std::fmt::Display for LitDifference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "hybrid score {:.5} over the lit rectangle, lit level moved by {:.2} %",
            self.score,
            self.shift * 100.0
        )
    }
}

/// [`LitDifference`] of `frame` against `golden`.
pub fn lit_difference(golden: &RgbImage, frame: &RgbImage) -> LitDifference {
    let background = *golden.get_pixel(0, 0);
    let (mut shift, mut level) = ([0i64; 3], [0i64; 3]);
    for (g, p) in golden.pixels().zip(frame.pixels()) {
        if *g != background || *p != background {
            for k in 0..3 {
                shift[k] += i64::from(p[k]) - i64::from(g[k]);
                level[k] += i64::from(g[k]);
            }
        }
    }
    // The channel whose level moved the most, against the mean level of all three.
    let total = level.iter().sum::<i64>().max(1) as f64 / 3.0;
    let shift = shift.iter().map(|&s| s.abs()).max().unwrap() as f64 / total;
    LitDifference {
        score: lit_score(golden, frame),
        shift,
    }
}

/// The hybrid score of `frame` against `golden` over the golden's lit rectangle: the background
/// (the colour of the golden's top-left pixel) around it would dilute the score.
pub fn lit_score(golden: &RgbImage, frame: &RgbImage) -> f64 {
    let (x, y, w, h) = lit_crop(golden);
    let crop = |image: &RgbImage| image::imageops::crop_imm(image, x, y, w, h).to_image();
    image_compare::rgb_hybrid_compare(&crop(golden), &crop(frame))
        .expect("same size")
        .score
}

/// The smallest rectangle (x, y, width, height) holding every pixel of `image` that is not the
/// colour of its top-left pixel.
pub fn lit_crop(image: &RgbImage) -> (u32, u32, u32, u32) {
    let background = *image.get_pixel(0, 0);
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for (x, y, p) in image.enumerate_pixels() {
        if *p != background {
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
    }
    assert!(x0 <= x1, "an image of one colour");
    (x0, y0, x1 - x0 + 1, y1 - y0 + 1)
}

/// `image` with each pixel that is not the background (its top-left pixel's colour) scaled by
/// `factor`.
pub fn dim_lit(image: &RgbImage, factor: f32) -> RgbImage {
    let background = *image.get_pixel(0, 0);
    let mut dimmed = image.clone();
    for p in dimmed.pixels_mut().filter(|p| **p != background) {
        p.0 = p.0.map(|c| (c as f32 * factor).round() as u8);
    }
    dimmed
}

/// An asset folder with `obj_text` as cylinder.obj, a flat normal map, and diffuse and specular
/// maps of one colour each.
#[track_caller]
pub fn flat_assets(name: &str, obj_text: &str, diffuse: [u8; 4], specular: [u8; 4]) -> PathBuf {
    let dir = scratch(name);
    std::fs::write(dir.join("cylinder.obj"), obj_text).unwrap();
    let size = 64;
    let texels = (size * size) as usize;
    let dds = |rgba: [u8; 4]| encode_dds_dxt3(rgba.repeat(texels), size).unwrap();
    std::fs::write(dir.join("diffuse.DDS"), dds(diffuse)).unwrap();
    std::fs::write(dir.join("specular.DDS"), dds(specular)).unwrap();
    let flat = encode_bmp(&vec![[128, 128, 255]; texels], size).unwrap();
    std::fs::write(dir.join("normal.bmp"), flat).unwrap();
    dir
}

/// A scratch asset folder (see [`scratch`]) for a scene that reads `scene`/diffuse.bmp and
/// `scene`/normal.bmp: a diffuse map of one colour and a flat normal map (128, 128, 255), `size`²
/// texels each.
#[track_caller]
pub fn flat_scene_assets(name: &str, scene: &str, size: u32, diffuse: [u8; 3]) -> PathBuf {
    let dir = scratch(name);
    std::fs::create_dir_all(dir.join(scene)).unwrap();
    let texels = (size * size) as usize;
    for (file, rgb) in [("diffuse.bmp", diffuse), ("normal.bmp", [128, 128, 255])] {
        let bmp = encode_bmp(&vec![rgb; texels], size).unwrap();
        std::fs::write(dir.join(scene).join(file), bmp).unwrap();
    }
    dir
}

/// The project's cylinder with a flat normal map and white diffuse and specular maps.
#[track_caller]
pub fn flat_white_assets(name: &str) -> PathBuf {
    let obj = std::fs::read_to_string(own_assets().join("cylinder.obj")).unwrap();
    flat_assets(name, &obj, [255; 4], [255; 4])
}

/// Window coordinates (x right, y down from the top row; pixel centres at +0.5) of a world point,
/// through the tutorial's start camera.
pub fn project(world: Vec3) -> (f32, f32) {
    let controls = Controls::default();
    let clip = controls.projection_matrix() * controls.view_matrix() * world.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    (
        (ndc.x + 1.0) * 0.5 * W as f32,
        (1.0 - ndc.y) * 0.5 * H as f32,
    )
}

/// The indexers' property, for proptest: on `soup` and `basis`, normalizing the tangents before
/// summing them or not, `index_vbo_tbn_hashed` picks the vertex the linear search picks (ties included) and
/// sums in the same order, and `index_vbo_hashed` merges exactly the corners the tutorial's map merges, so
/// indices, vertices and sums are identical to the bit ([`mesh_bit_difference`]).
pub fn indexers_match_references(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    normalize: bool,
) -> Result<(), TestCaseError> {
    let options = IndexOptions {
        normalize_before_sum: normalize,
    };
    let fast = index_vbo_tbn_hashed(soup, basis, options);
    let linear = vboindexer::index_vbo_tbn(soup, basis, options);
    if let Some(difference) = mesh_bit_difference(&fast, &linear) {
        return Err(TestCaseError::fail(format!(
            "index_vbo_tbn_hashed against the linear search: {difference}"
        )));
    }
    if let Some(difference) =
        mesh_bit_difference(&index_vbo_hashed(soup), &vboindexer::index_vbo(soup))
    {
        return Err(TestCaseError::fail(format!(
            "index_vbo_hashed against the tutorial's map: {difference}"
        )));
    }
    Ok(())
}

/// The first place where `a` and `b` differ to the bit (index width, an index, an array's length or
/// one float's bits: 0.0 and -0.0 differ, a NaN equals the same NaN), or None.
pub fn mesh_bit_difference(a: &IndexedMesh, b: &IndexedMesh) -> Option<String> {
    if a.indices.index_size() != b.indices.index_size() || a.indices.len() != b.indices.len() {
        return Some(format!(
            "{} indices of {} bytes against {} of {}",
            a.indices.len(),
            a.indices.index_size(),
            b.indices.len(),
            b.indices.index_size()
        ));
    }
    if let Some(i) = (0..a.indices.len()).find(|&i| a.indices.get(i) != b.indices.get(i)) {
        let (x, y) = (a.indices.get(i), b.indices.get(i));
        return Some(format!("indices[{i}]: {x} against {y}"));
    }
    let arrays: [(&str, Vec<f32>, Vec<f32>); 5] = [
        ("vertices", floats(&a.vertices), floats(&b.vertices)),
        ("uvs", floats(&a.uvs), floats(&b.uvs)),
        ("normals", floats(&a.normals), floats(&b.normals)),
        ("tangents", floats(&a.tangents), floats(&b.tangents)),
        ("bitangents", floats(&a.bitangents), floats(&b.bitangents)),
    ];
    for (name, x, y) in arrays {
        if x.len() != y.len() {
            return Some(format!("{name}: {} floats against {}", x.len(), y.len()));
        }
        if let Some(i) = (0..x.len()).find(|&i| x[i].to_bits() != y[i].to_bits()) {
            return Some(format!("{name}, float {i}: {:?} against {:?}", x[i], y[i]));
        }
    }
    None
}

fn floats<T: bytemuck::Pod>(values: &[T]) -> Vec<f32> {
    bytemuck::cast_slice(values).to_vec()
}

/// Checks a picture the docs show against what a test makes: bit for bit on the reference
/// renderer, where it was made, a hybrid similarity of at least 0.95 elsewhere. With
/// TUTORIAL13_UPDATE_DOCS=1 it writes the picture instead. `module` names the tests that make it.
pub fn check_docs_picture(picture: &RgbImage, docs_path: &str, module: &str) {
    let path = manifest().join(docs_path);
    if std::env::var_os("TUTORIAL13_UPDATE_DOCS").is_some() {
        picture.save(&path).unwrap();
        println!("{docs_path} rewritten (TUTORIAL13_UPDATE_DOCS)");
        return;
    }
    let committed = image::open(&path)
        .unwrap_or_else(|e| panic!("{docs_path}: {e}"))
        .into_rgb8();
    let context = tutorial13::gl::context::HeadlessContext::new(Profile::Core, false).unwrap();
    if not_reference_renderer(context.info()).is_none() {
        let (differing, max, _) = pixel_diff(&committed, picture);
        assert!(
            differing == 0,
            "{docs_path}: {differing} pixels differ (by up to {max}) from what the commands make; \
             rewrite it with: TUTORIAL13_UPDATE_DOCS=1 cargo test --release -- {module}::"
        );
        return;
    }
    let name = Path::new(docs_path)
        .file_stem()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    let similarity = hybrid_score(&committed, picture, &name, 0.95);
    assert!(
        similarity >= 0.95,
        "{docs_path} is not what the commands make ({similarity:.4}); rewrite it with: \
         TUTORIAL13_UPDATE_DOCS=1 cargo test --release -- {module}::"
    );
}

/// `obj` as a sculpt's export writes it: no UV layout (the `vt` lines dropped, each corner
/// `v/vt/vn` written `v//vn`), as ZBrush and Blender's sculpt exports do.
pub fn without_uvs(obj: &str) -> String {
    obj.lines()
        .filter(|l| !l.starts_with("vt "))
        .map(|l| match l.strip_prefix("f ") {
            Some(corners) => {
                let corners: Vec<String> = corners
                    .split(' ')
                    .map(|c| {
                        let parts: Vec<&str> = c.split('/').collect();
                        format!("{}//{}", parts[0], parts[2])
                    })
                    .collect();
                format!("f {}\n", corners.join(" "))
            }
            None => format!("{l}\n"),
        })
        .collect()
}
