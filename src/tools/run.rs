//! A scene, run as the tutorial runs it (in a window) or headless (`--headless`, `--bench`): the
//! program's default command.

use std::path::{Path, PathBuf};

use crate::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use crate::frontends::window::{run_window, WindowOptions};
use crate::gl::image::{write_screenshot, ImageFormat};
use crate::gl::Profile;
use crate::scenes::{self, SceneDescriptor, SceneOptions};
use crate::statistics::min_median;
use crate::tools::tour::{check_exercise, tour_request, TourRequest};
use crate::tools::{parse_size, SizeOf};
use crate::tour::Step;
use crate::{Error, Result};

// The global flags; each scene's own arguments are added by `scenes::command_line`, under a heading
// per scene. (No doc comment: on a flattened struct clap would take it for the program's about.)
#[derive(clap::Args, Debug, Clone)]
pub struct RunOptions {
    /// Which program to run (see the list below)
    #[arg(long, value_name = "NAME", default_value = "cylinder", value_parser = scenes::find)]
    pub scene: &'static SceneDescriptor,

    /// Folder with the scenes' files (docs/scenes.md lists them; the tutorial's own cylinder.obj,
    /// diffuse.DDS, normal.bmp and specular.DDS work unchanged). A file it lacks is taken from the
    /// crate's assets/, and a notice names it [default: the crate's assets/]
    #[arg(long, value_name = "DIR")]
    pub assets: Option<PathBuf>,

    /// Folder with the .vertexshader/.fragmentshader files [default: the crate's shaders/, else the
    /// copies built into the binary]
    #[arg(long, value_name = "DIR")]
    pub shaders: Option<PathBuf>,

    /// No window: render through EGL on Mesa (no display or X server needed)
    #[arg(long)]
    pub headless: bool,

    /// Render N frames (N ≥ 1) with time frozen at 0, then exit
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,

    /// Write the last frame to this file: .png, .bmp or .tga by its extension
    #[arg(long, value_name = "FILE.png")]
    pub screenshot: Option<PathBuf>,

    /// Framebuffer size
    #[arg(long, value_name = "WxH", default_value = "1024x768", value_parser = |s: &str| parse_size(s, SizeOf::Pixels))]
    pub size: (u32, u32),

    /// OpenGL profile of the context
    #[arg(long, value_enum, default_value_t = Profile::Core)]
    pub profile: Profile,

    /// Render K headless frames (K ≥ 1), each timed to completion, and print min/median ms/frame
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..))]
    pub bench: Option<u32>,

    /// Multisampling: N samples per pixel (0 = none, as the tutorial's published screenshot; 4 is
    /// what the original gets on Mesa under X), in the window and headless alike
    #[arg(long, value_name = "N", default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=32))]
    pub msaa: u8,

    /// Draw the window's panel (keys, switches, sliders) into the --screenshot too. The window shows
    /// it at start (F1 hides it); its P saves the frame alone, Ctrl+P the window as shown
    #[arg(long)]
    pub panel: bool,

    /// In the window: time K frames with the panel shown and K with it hidden, alternating every 50,
    /// and print min/median ms/frame of each and their ratio (what the panel costs)
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..),
          conflicts_with_all = ["headless", "bench", "frames", "screenshot"])]
    pub bench_panel: Option<u32>,

    /// Headless: use a GPU's EGL device where there is one instead of Mesa's llvmpipe
    #[arg(long)]
    pub prefer_hardware: bool,

    /// The tutorial's sections as steps: `list` prints them; a number or name starts at that step,
    /// its code in a pane (PageDown / PageUp step)
    #[arg(long, value_name = "N|NAME|list")]
    pub tour: Option<String>,

    /// Check the tutorial's exercise N (1 or 2): one line, exit 0 only when your frame matches
    #[arg(long, value_name = "N", requires = "headless", conflicts_with_all = ["tour", "bench", "frames", "screenshot"],
          value_parser = clap::value_parser!(u8).range(1..=2))]
    pub check_exercise: Option<u8>,
}

/// Runs `options.scene` with `scene`'s options: headless with `--headless` or `--bench`, else in
/// the window. What can be refused without a context (the screenshot's name and folder, the
/// `--assets` and `--shaders` folders) is refused first.
pub fn run(options: &RunOptions, scene: SceneOptions) -> Result<()> {
    let step = match options.tour.as_deref().map(tour_request).transpose()? {
        Some(TourRequest::List) => {
            print!("{}", crate::tour::list());
            return Ok(());
        }
        Some(TourRequest::Step(step)) => Some(step),
        None => None,
    };
    check_paths(options)?;
    if let Some(n) = options.check_exercise {
        println!("{}", check_exercise(n, &headless_options(options, scene))?);
        Ok(())
    } else if options.headless || options.bench.is_some() {
        run_headless(options, scene, step)
    } else {
        // The key list is printed once the window is up (a failure before prints its error alone).
        let descriptor = match step {
            Some(step) => step.state.descriptor()?,
            None => options.scene,
        };
        run_window(WindowOptions {
            descriptor,
            tour: step,
            scene,
            size: options.size,
            profile: options.profile,
            frames: options.frames,
            screenshot: options.screenshot.clone(),
            msaa: options.msaa,
            panel: options.panel,
            bench_panel: options.bench_panel,
        })
    }
}

/// Refused before rendering, not after a frame (or a whole window session) has been drawn.
fn check_paths(options: &RunOptions) -> Result<()> {
    if let Some(path) = &options.screenshot {
        crate::files::check_output("--screenshot", path, ImageFormat::from_path)?;
    }
    // A mistyped folder would otherwise fall back silently (--shaders) or fail later on one file.
    for (flag, dir) in [
        ("--assets", &options.assets),
        ("--shaders", &options.shaders),
    ] {
        if let Some(dir) = dir.as_deref().filter(|dir| !dir.is_dir()) {
            let reason = if dir.exists() {
                "not a folder"
            } else {
                "no such folder"
            };
            return Err(Error::Argument(format!(
                "{flag} {}: {reason}",
                dir.display()
            )));
        }
    }
    Ok(())
}

/// What the command line asks to render headless.
fn headless_options(options: &RunOptions, scene: SceneOptions) -> HeadlessOptions {
    let (width, height) = options.size;
    HeadlessOptions {
        descriptor: options.scene,
        scene,
        width,
        height,
        profile: options.profile,
        prefer_hardware: options.prefer_hardware,
        msaa: options.msaa.into(),
    }
}

/// `--headless` and `--bench`: the timings printed, then the last of `--frames` frames saved; with
/// `--tour N`, of that step.
fn run_headless(
    options: &RunOptions,
    scene: SceneOptions,
    step: Option<&'static Step>,
) -> Result<()> {
    let (width, height) = options.size;
    let mut headless = headless_options(options, scene);
    if let Some(step) = step {
        headless.descriptor = step.state.descriptor()?;
    }
    let mut renderer = HeadlessRenderer::new(&headless)?;
    if let Some(step) = step {
        renderer.host.set_step_state(step)?;
    }
    log::info!("{}", renderer.host.gl().info);
    if options.panel {
        renderer.host.show_panel()?;
    }
    if let Some(k) = options.bench {
        let times = renderer.bench(k)?;
        let (min, median) = min_median(&times);
        println!(
            "{k} frames at {width}x{height}: min {min:.3} ms/frame, median {median:.3} ms/frame"
        );
    }
    if options.bench.is_none() || options.screenshot.is_some() {
        let frames = options.frames.unwrap_or(1);
        let image = renderer.render_frames(frames)?;
        match &options.screenshot {
            Some(path) => save(path, &image)?,
            None => log::warn!(
                "rendered {frames} frame(s) and wrote nothing: add --screenshot FILE.png to save \
                 the last one"
            ),
        }
    }
    Ok(())
}

fn save(path: &Path, image: &image::RgbaImage) -> Result<()> {
    write_screenshot(path, image).map_err(|error| Error::Screenshot {
        error: Box::new(error),
    })?;
    log::info!("wrote {}", path.display());
    Ok(())
}
