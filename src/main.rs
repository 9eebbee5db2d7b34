//! `tutorial13`: the binary. The command line is the contract in DESIGN.md; `--help` lists the keys.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::window::{run_window, WindowOptions};
use tutorial13::frontends::{key_list, min_median};
use tutorial13::gl::image::write_screenshot;
use tutorial13::gl::Profile;
use tutorial13::normalmap::{Green, Kernel};
use tutorial13::scenes::{self, SceneDescriptor, SceneOptions, SCENES};

/// The global flags; each scene's own arguments are added by [`scenes::command_line`], under a
/// heading per scene.
#[derive(Parser, Debug)]
#[command(
    name = "tutorial13",
    version,
    about = "opengl-tutorial.org's Tutorial 13 (Normal Mapping), ported to Rust",
    after_help = help_text(),
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,

    /// Which program to run (see the list below)
    #[arg(long, value_name = "NAME", default_value = "cylinder", value_parser = scenes::find)]
    scene: &'static SceneDescriptor,

    /// Folder with the scenes' files (docs/scenes.md lists them; the tutorial's own cylinder.obj,
    /// diffuse.DDS, normal.bmp and specular.DDS work unchanged). A file it lacks is taken from the
    /// crate's assets/, and a notice names it [default: the crate's assets/]
    #[arg(long, value_name = "DIR")]
    assets: Option<PathBuf>,

    /// Folder with the .vertexshader/.fragmentshader files [default: the crate's shaders/, else the
    /// copies built into the binary]
    #[arg(long, value_name = "DIR")]
    shaders: Option<PathBuf>,

    /// No window: render through EGL on Mesa (no display or X server needed)
    #[arg(long)]
    headless: bool,

    /// Render N frames (N ≥ 1) with time frozen at 0, then exit
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    frames: Option<u32>,

    /// Write the last frame to this file: .png, .bmp or .tga by its extension
    #[arg(long, value_name = "FILE.png")]
    screenshot: Option<PathBuf>,

    /// Framebuffer size
    #[arg(long, value_name = "WxH", default_value = "1024x768", value_parser = parse_size)]
    size: (u32, u32),

    /// OpenGL profile of the context
    #[arg(long, value_enum, default_value_t = Profile::Core)]
    profile: Profile,

    /// Render K headless frames (K ≥ 1), each timed to completion, and print min/median ms/frame
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..))]
    bench: Option<u32>,

    /// Multisampling: N samples per pixel (0 = none, as the tutorial's published screenshot; 4 is
    /// what the original gets on Mesa under X), in the window and headless alike
    #[arg(long, value_name = "N", default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=32))]
    msaa: u8,

    /// Draw the window's panel (keys, switches, sliders) into the --screenshot too. The window shows
    /// it at start (F1 hides it); its P saves the frame alone, Ctrl+P the window as shown
    #[arg(long)]
    panel: bool,

    /// In the window: time K frames with the panel shown and K with it hidden, alternating every 50,
    /// and print min/median ms/frame of each and their ratio (what the panel costs)
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..),
          conflicts_with_all = ["headless", "bench", "frames", "screenshot"])]
    bench_panel: Option<u32>,

    /// Headless: use a GPU's EGL device where there is one instead of Mesa's llvmpipe
    #[arg(long)]
    prefer_hardware: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Generate the project's own assets (cylinder, brick textures, normal map) into a folder
    MakeAssets {
        /// Output folder (created if missing) [default: the crate's assets/, where the program reads
        /// them]
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Replace files that are already there with other contents (e.g. the tutorial's own files);
        /// without it such files are named and nothing is written
        #[arg(long)]
        force: bool,
    },
    /// Make a tangent-space normal map from a grey-scale height map (white high, black low; any size;
    /// edges wrap so that tiling maps tile), or guess one from a photo (--from-photo)
    Normalmap {
        /// The height map: PNG, BMP, TGA or JPEG, 8 or 16 bits (colour is read as luma); with
        /// --from-photo, the photo
        height: PathBuf,
        /// Output: .bmp (24-bit, what the tutorial loads) or .png
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
        /// Texels of relief that black-to-white stands for (larger = bumpier; negative turns the
        /// relief inside out)
        #[arg(
            long,
            value_name = "S",
            default_value_t = 8.0,
            allow_negative_numbers = true
        )]
        strength: f32,
        /// Green channel up the picture (OpenGL, the tutorial) or down (DirectX)
        #[arg(long, value_enum, default_value_t = Green::Up)]
        green: Green,
        /// Store x and y only (blue 0); readers rebuild z = sqrt(1 - x² - y²)
        #[arg(long)]
        two_channel: bool,
        /// Derivative filter
        #[arg(long, value_enum, default_value_t = Kernel::Sobel)]
        kernel: Kernel,
        /// Turn the map by 180° (red and green negated): the tutorial's own cylinder (scene
        /// cylinder without --model) shows every map that way round, so white looks raised there
        /// only with this. Not for --model, the wall or other programs (README: "Which way is up")
        #[arg(long)]
        invert: bool,
        /// Guess the relief from one photo instead, CrazyBump's way (a guess: see the README)
        ///
        /// The photo's luminance (sRGB decoded to linear light) minus a wide blur of it (--radius)
        /// is taken as the height: brighter than its surroundings = higher. It reads brightness, not
        /// shape: a dark stain or joint becomes a dent, a light one a ridge; an engraved shape lit
        /// from the front comes out raised; a bump lit from one side is shifted and flattened.
        /// Several photos under known lights (`tutorial13 photometric`) measure the surface instead
        #[arg(long)]
        from_photo: bool,
        /// With --from-photo: brightness changes wider than about R texels are removed (the blur is
        /// three box blurs of 2R+1 texels, near a Gaussian of σ ≈ R)
        #[arg(long, value_name = "R", default_value_t = tutorial13::photo::DEFAULT_RADIUS,
              requires = "from_photo", value_parser = clap::value_parser!(u32).range(1..=4096))]
        radius: u32,
    },
    /// Photometric stereo: a normal map (and albedo) from three or more photos under known lights
    ///
    /// Photos of a matte surface from one camera position, each lit by one distant light from a
    /// known direction, all equally bright (one lamp at one distance, exposure locked). Photos are
    /// read as sRGB (or --linear) and solved in linear light, Lambert's law by least squares. Per
    /// texel, photos where it is near black (--shadow) or saturated (98 % of full scale) are left
    /// out; texels left with fewer than three, or with lights within 5° of one plane, get the flat
    /// normal and are counted on stderr. Shine, a lamp close to the surface and light bounced
    /// between its parts break the model
    Photometric {
        /// The photos (PNG, JPEG, TGA or BMP, 8 or 16 bits), all the same size
        photos: Vec<PathBuf>,
        /// Direction towards the light of each photo, in the photos' order: x to the photo's right,
        /// y up it, z out of the surface towards the camera; any length (e.g. --light -1,0,1)
        #[arg(long = "light", value_name = "X,Y,Z", allow_hyphen_values = true)]
        lights: Vec<String>,
        /// Output normal map: .bmp (24-bit, what the tutorial loads) or .png
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
        /// Also write the albedo (the surface's colour without the lighting), .bmp or .png, encoded
        /// as the photos are
        #[arg(long, value_name = "FILE")]
        albedo: Option<PathBuf>,
        /// Green channel up the picture (OpenGL, the tutorial) or down (DirectX)
        #[arg(long, value_enum, default_value_t = Green::Up)]
        green: Green,
        /// The photos are linear already (a raw converter's linear output, a render), not sRGB
        #[arg(long)]
        linear: bool,
        /// Linear luminance below which a photo's texel counts as shadow and is left out
        #[arg(long, value_name = "L", default_value_t = tutorial13::photometric::DEFAULT_SHADOW)]
        shadow: f32,
    },
}

fn parse_size(s: &str) -> std::result::Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WxH, e.g. 1024x768"))?;
    let parse = |v: &str| {
        v.parse::<u32>()
            .ok()
            .filter(|&n| (1..=16384).contains(&n))
            .ok_or_else(|| format!("'{v}' is not a size from 1 to 16384"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// `--help`'s closing text: the scenes, then each scene's keys.
fn help_text() -> String {
    let mut text = String::from("Scenes (--scene NAME):");
    for scene in SCENES {
        text.push_str(&format!("\n  {:<15} {}", scene.name, scene.description));
    }
    for scene in SCENES {
        text.push_str(&format!("\n\n{}", key_list(scene)));
    }
    text
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .format_timestamp(None)
        .format_target(false)
        .init();
    let (cli, scene) = parse();
    match run(cli, scene) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the context chain, outermost first.
            eprintln!("tutorial13: {}", format!("{e:#}").replace('\n', " | "));
            ExitCode::FAILURE
        }
    }
}

/// The global flags, and every scene's options (a flag of a scene other than `--scene`'s is an
/// error, printed by clap like any other command-line error).
fn parse() -> (Cli, SceneOptions) {
    let mut command = scenes::command_line(Cli::command());
    let matches = command.get_matches_mut();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    let options = SceneOptions {
        assets: cli.assets.clone(),
        shaders: cli.shaders.clone(),
        ..Default::default()
    };
    let options = scenes::scene_options(&matches, cli.scene, options).unwrap_or_else(|message| {
        command
            .error(clap::error::ErrorKind::ArgumentConflict, message)
            .exit()
    });
    (cli, options)
}

fn run(cli: Cli, scene: SceneOptions) -> Result<()> {
    if let Some(Command::Normalmap {
        height,
        output,
        strength,
        green,
        two_channel,
        kernel,
        invert,
        from_photo,
        radius,
    }) = &cli.command
    {
        use tutorial13::normalmap::{normal_map, write_normal_map, HeightMap};
        use tutorial13::photo::{height_from_photo, Photo};
        if !strength.is_finite() {
            anyhow::bail!("--strength {strength}: must be a finite number");
        }
        let heights = match from_photo {
            true => height_from_photo(&Photo::load(height)?, *radius),
            false => HeightMap::load(height)?,
        };
        let options = tutorial13::normalmap::NormalMapOptions {
            // Both slopes negated: the same as the height turned inside out.
            strength: if *invert { -strength } else { *strength },
            kernel: *kernel,
            green: *green,
            two_channel: *two_channel,
        };
        let texels = normal_map(&heights, options);
        write_normal_map(output, &texels, heights.width, heights.height)?;
        println!(
            "wrote {} ({}x{})",
            output.display(),
            heights.width,
            heights.height
        );
        return Ok(());
    }
    if let Some(Command::Photometric {
        photos,
        lights,
        output,
        albedo,
        green,
        linear,
        shadow,
    }) = &cli.command
    {
        use tutorial13::photo::Encoding;
        let recovered = tutorial13::photometric::run(&tutorial13::photometric::Job {
            photos,
            lights,
            output,
            albedo: albedo.as_deref(),
            encoding: if *linear {
                Encoding::Linear
            } else {
                Encoding::Srgb
            },
            green: *green,
            shadow: *shadow,
        })?;
        let (w, h, flat) = (recovered.width, recovered.height, recovered.unsolved);
        if flat > 0 {
            log::warn!(
                "{flat} of {} texels kept fewer than three photos (or photos whose lights are \
                 nearly coplanar): flat normal there",
                w as usize * h as usize
            );
        }
        let albedo = albedo.iter().map(|a| format!(" and {}", a.display()));
        println!(
            "wrote {}{} ({w}x{h})",
            output.display(),
            albedo.collect::<String>()
        );
        return Ok(());
    }
    if let Some(Command::MakeAssets { out, force }) = &cli.command {
        let files = scenes::generate_assets()?;
        // Where the program reads them unless told otherwise, wherever this is run from.
        let out = out.clone().unwrap_or_else(scenes::crate_assets_dir);
        let written = tutorial13::assets::make_assets(&out, &files, *force)?;
        let names = |paths: &[PathBuf]| {
            let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
            names.join(", ")
        };
        for (what, paths) in [
            ("created", &written.created),
            ("replaced", &written.replaced),
            ("unchanged", &written.unchanged),
        ] {
            if !paths.is_empty() {
                println!("{what}: {}", names(paths));
            }
        }
        return Ok(());
    }
    // Refused before rendering, not after a frame (or a whole window session) has been drawn.
    if let Some(path) = &cli.screenshot {
        tutorial13::gl::image::ImageFormat::from_path(path)?;
        // A missing folder would only show after the frame (or a whole window session) was drawn.
        let folder = path.parent().filter(|f| !f.as_os_str().is_empty());
        if let Some(folder) = folder.filter(|f| !f.is_dir()) {
            anyhow::bail!(
                "--screenshot {}: no such folder {} (create it first)",
                path.display(),
                folder.display()
            );
        }
    }
    // A mistyped folder would otherwise fall back silently (--shaders) or fail later on one file.
    for (flag, dir) in [("--assets", &cli.assets), ("--shaders", &cli.shaders)] {
        if let Some(dir) = dir.as_deref().filter(|dir| !dir.is_dir()) {
            let reason = if dir.exists() {
                "not a folder"
            } else {
                "no such folder"
            };
            anyhow::bail!("{flag} {}: {reason}", dir.display());
        }
    }
    if cli.headless || cli.bench.is_some() {
        run_headless(&cli, scene)
    } else {
        // The key list is printed once the window is up (a failure before prints its error alone).
        run_window(WindowOptions {
            descriptor: cli.scene,
            scene,
            size: cli.size,
            profile: cli.profile,
            frames: cli.frames,
            screenshot: cli.screenshot.clone(),
            msaa: cli.msaa,
            panel: cli.panel,
            bench_panel: cli.bench_panel,
        })
        .map_err(anyhow::Error::from)
    }
}

fn run_headless(cli: &Cli, scene: SceneOptions) -> Result<()> {
    let (width, height) = cli.size;
    let mut renderer = HeadlessRenderer::new(&HeadlessOptions {
        descriptor: cli.scene,
        scene,
        width,
        height,
        profile: cli.profile,
        prefer_hardware: cli.prefer_hardware,
        msaa: cli.msaa.into(),
    })?;
    log::info!("{}", renderer.context.info());
    if cli.panel {
        renderer.show_panel()?;
    }
    if let Some(k) = cli.bench {
        let times = renderer.bench(k)?;
        let (min, median) = min_median(&times);
        println!(
            "{k} frames at {width}x{height}: min {min:.3} ms/frame, median {median:.3} ms/frame"
        );
    }
    if cli.bench.is_none() || cli.screenshot.is_some() {
        let frames = cli.frames.unwrap_or(1);
        let image = renderer.render_frames(frames)?;
        match &cli.screenshot {
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
    write_screenshot(path, image).with_context(|| "cannot save the screenshot".to_string())?;
    log::info!("wrote {}", path.display());
    Ok(())
}
