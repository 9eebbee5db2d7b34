//! `tutorial13`: the binary. The command line is the contract in DESIGN.md; `--help` lists the keys.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use tutorial13::common::tangentspace::TangentOptions;
use tutorial13::common::vboindexer::IndexOptions;
use tutorial13::debug::compare::CompareMode;
use tutorial13::debug::lines::LineMode;
use tutorial13::debug::views::{ColorView, NormalMapConvention, ShaderSwitches};
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::window::{run_window, WindowOptions};
use tutorial13::frontends::{key_list, min_median};
use tutorial13::gl::image::write_screenshot;
use tutorial13::gl::Profile;
use tutorial13::mesh::MeshOptions;
use tutorial13::scenes::cube::CubeOptions;
use tutorial13::scenes::cylinder::{CompareOptions, CylinderOptions};
use tutorial13::scenes::sprite::SpriteOptions;
use tutorial13::scenes::wall::{LightingSpace, WallOptions};
use tutorial13::scenes::{SceneName, SceneOptions};
use tutorial13::tangents::TangentSource;

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
    #[arg(long, value_name = "NAME", default_value = "cylinder")]
    scene: SceneName,

    /// Folder with cylinder.obj, diffuse.DDS, normal.bmp and specular.DDS (the tutorial's own files
    /// work unchanged) [default: the crate's assets/]
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
    #[arg(long, value_enum, default_value_t = ProfileArg::Core)]
    profile: ProfileArg,

    /// Start with the TBN debug lines on (key L toggles them)
    #[arg(long)]
    debug_lines: bool,

    /// How to draw the debug lines: the tutorial's immediate mode (needs --profile compat) or a line
    /// shader [default: immediate mode where the context allows it, else the shader, with a notice]
    #[arg(long, value_enum, value_name = "MODE")]
    debug_lines_mode: Option<LineModeArg>,

    /// Colour view: lit, light, light01, eye, eye01, normal, normal01, optionally .x/.y/.z (key V)
    #[arg(long, value_name = "NAME", default_value = "lit")]
    view: ColorView,

    /// Exercise 1: normalize tangents and bitangents before summing them (key N)
    #[arg(long)]
    normalize_before_sum: bool,

    /// Skip the Gram-Schmidt step of the tangent basis (key G)
    #[arg(long)]
    no_gram_schmidt: bool,

    /// Skip the handedness fix of the tangent basis (key H)
    #[arg(long)]
    no_handedness: bool,

    /// Constant specular colour 0.3 instead of the specular texture (key S)
    #[arg(long)]
    no_specular_texture: bool,

    /// Normalize the camera-space T, B, N as the article's text does (key T)
    #[arg(long)]
    normalize_tbn: bool,

    /// Cube scene: start with normal mapping off (key N)
    #[arg(long)]
    no_normal_map: bool,

    /// Render K headless frames (K ≥ 1), each timed to completion, and print min/median ms/frame
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..))]
    bench: Option<u32>,

    /// Multisampling: N samples per pixel (0 = none, as the tutorial's published screenshot; 4 is
    /// what the original gets on Mesa under X), in the window and headless alike
    #[arg(long, value_name = "N", default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=32))]
    msaa: u8,

    /// Where the tangent frame comes from: the tutorial's computeTangentBasis + indexVBO_TBN,
    /// MikkTSpace, or none (a per-pixel frame from screen-space derivatives) (key F)
    #[arg(long, value_name = "SOURCE", default_value = "tutorial")]
    tangents: TangentSource,

    /// Compare two tangent sources in one frame: A left of the split line, B right of it
    /// (e.g. tutorial,mikktspace) (key K; A and D move the split)
    #[arg(long, value_name = "A,B", value_parser = parse_pair)]
    compare: Option<[TangentSource; 2]>,

    /// With --compare: show the per-pixel difference as a heat map (its largest difference is
    /// printed and in the title) instead of the two sides
    #[arg(long, requires = "compare")]
    compare_difference: bool,

    /// With --compare: where the split line is, as a fraction of the width from the left
    #[arg(long, value_name = "F", default_value_t = 0.5, value_parser = parse_fraction, requires = "compare")]
    split: f32,

    /// Normal map's green channel: up the picture (OpenGL, the tutorial's) or down (DirectX); the
    /// cylinder and sprite scenes (key Y)
    #[arg(long, value_enum, value_name = "DIR", default_value_t = GreenArg::Up)]
    green: GreenArg,

    /// Read normal-map bytes as c*255/127-128/127 (128 is exactly 0) instead of 2c-1 (key E)
    #[arg(long)]
    exact_expansion: bool,

    /// The normal map holds x and y only; rebuild z = sqrt(1 - x² - y²) (key Z)
    #[arg(long)]
    two_channel: bool,

    /// Scene wall: light the stone wall in view space, in tangent space, or without its normal map
    /// (key S)
    #[arg(long, value_name = "SPACE", default_value = "view")]
    space: LightingSpace,

    /// Headless: use a GPU's EGL device where there is one instead of Mesa's llvmpipe
    #[arg(long)]
    prefer_hardware: bool,

    /// Sprite scene: the light at X,Y (0 to 1 across the window, y up as in the article) and height
    /// Z > 0 [default: 0.4,0.6,0.075]; in the window the mouse takes over once it moves
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_light)]
    light: Option<glam::Vec3>,

    /// Sprite scene: measure the light's distance in the sprite's own pixels, not in window heights
    /// (key I)
    #[arg(long)]
    independent_falloff: bool,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum ProfileArg {
    Core,
    Compat,
}

impl From<ProfileArg> for Profile {
    fn from(p: ProfileArg) -> Self {
        match p {
            ProfileArg::Core => Profile::Core,
            ProfileArg::Compat => Profile::Compat,
        }
    }
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum LineModeArg {
    Legacy,
    Shader,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Generate the project's own assets (cylinder, brick textures, normal map) into a folder
    MakeAssets {
        /// Output folder (created if missing)
        #[arg(long, value_name = "DIR", default_value = "assets")]
        out: PathBuf,
        /// Replace files that are already there with other contents (e.g. the tutorial's own files);
        /// without it such files are named and nothing is written
        #[arg(long)]
        force: bool,
    },
    /// Make a tangent-space normal map from a grey-scale height map (white high, black low; any size;
    /// edges wrap so that tiling maps tile)
    Normalmap {
        /// The height map: PNG, BMP or TGA, 8 or 16 bits (colour is read as luma)
        height: PathBuf,
        /// Output: .bmp (24-bit, what the tutorial loads) or .png
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
        /// Texels of relief that black-to-white stands for (larger = bumpier)
        #[arg(long, value_name = "S", default_value_t = 8.0)]
        strength: f32,
        /// Green channel up the picture (OpenGL, the tutorial) or down (DirectX)
        #[arg(long, value_enum, default_value_t = GreenArg::Up)]
        green: GreenArg,
        /// Store x and y only (blue 0); readers rebuild z = sqrt(1 - x² - y²)
        #[arg(long)]
        two_channel: bool,
        /// Derivative filter
        #[arg(long, value_enum, default_value_t = KernelArg::Sobel)]
        kernel: KernelArg,
    },
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum GreenArg {
    Up,
    Down,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum KernelArg {
    Sobel,
    Scharr,
    Central,
}

fn parse_pair(s: &str) -> std::result::Result<[TangentSource; 2], String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}' is not A,B, e.g. tutorial,mikktspace"))?;
    Ok([a.trim().parse()?, b.trim().parse()?])
}

fn parse_fraction(s: &str) -> std::result::Result<f32, String> {
    s.parse::<f32>()
        .ok()
        .filter(|f| (0.0..=1.0).contains(f))
        .ok_or_else(|| format!("'{s}' is not a number from 0 to 1"))
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

fn parse_light(s: &str) -> std::result::Result<glam::Vec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y, z] = parts[..] else {
        return Err(format!("'{s}' is not X,Y,Z, e.g. 0.5,0.5,0.075"));
    };
    let parse = |v: &str| {
        v.parse::<f32>()
            .ok()
            .filter(|n| n.is_finite())
            .ok_or_else(|| format!("'{v}' is not a finite number"))
    };
    let light = glam::Vec3::new(parse(x)?, parse(y)?, parse(z)?);
    if light.z <= 0.0 {
        return Err(format!(
            "Z = {} must be above 0 (the light's height over the sprite)",
            light.z
        ));
    }
    Ok(light)
}

/// `--help`'s closing text: the scenes, then each scene's keys.
fn help_text() -> String {
    let mut text = String::from("Scenes (--scene NAME):");
    for &scene in SceneName::ALL {
        text.push_str(&format!("\n  {:<15} {}", scene.name(), scene.description()));
    }
    for &scene in SceneName::ALL {
        text.push_str(&format!("\n\n{}", key_list(scene)));
    }
    text
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .format_timestamp(None)
        .format_target(false)
        .init();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the context chain, outermost first.
            eprintln!("tutorial13: {}", format!("{e:#}").replace('\n', " | "));
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    if let Some(Command::Normalmap {
        height,
        output,
        strength,
        green,
        two_channel,
        kernel,
    }) = &cli.command
    {
        use tutorial13::normalmap::{normal_map, write_normal_map, Green, HeightMap, Kernel};
        if !strength.is_finite() {
            anyhow::bail!("--strength {strength}: must be a finite number");
        }
        let heights = HeightMap::load(height)?;
        let options = tutorial13::normalmap::NormalMapOptions {
            strength: *strength,
            kernel: match kernel {
                KernelArg::Sobel => Kernel::Sobel,
                KernelArg::Scharr => Kernel::Scharr,
                KernelArg::Central => Kernel::Central,
            },
            green: match green {
                GreenArg::Up => Green::Up,
                GreenArg::Down => Green::Down,
            },
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
    if let Some(Command::MakeAssets { out, force }) = &cli.command {
        let written = tutorial13::assets::make_assets(out, *force)?;
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
    let scene = SceneOptions {
        assets: cli.assets.clone(),
        shaders: cli.shaders.clone(),
        cylinder: CylinderOptions {
            mesh: MeshOptions {
                tangents: TangentOptions {
                    gram_schmidt: !cli.no_gram_schmidt,
                    handedness: !cli.no_handedness,
                },
                indexing: IndexOptions {
                    normalize_before_sum: cli.normalize_before_sum,
                },
            },
            switches: ShaderSwitches {
                normalize_tbn: cli.normalize_tbn,
                specular_texture: !cli.no_specular_texture,
                view: cli.view,
                convention: NormalMapConvention {
                    green_down: cli.green == GreenArg::Down,
                    exact_expansion: cli.exact_expansion,
                    two_channel: cli.two_channel,
                },
            },
            debug_lines: cli.debug_lines,
            line_mode: cli.debug_lines_mode.map(|m| match m {
                LineModeArg::Legacy => LineMode::Legacy,
                LineModeArg::Shader => LineMode::Shader,
            }),
            tangents: cli.tangents,
            compare: cli.compare.map(|sources| CompareOptions {
                sources,
                mode: if cli.compare_difference {
                    CompareMode::Difference
                } else {
                    CompareMode::Split
                },
                split: cli.split,
            }),
        },
        wall: WallOptions { space: cli.space },
        sprite: SpriteOptions {
            light: cli.light.unwrap_or(SpriteOptions::default().light),
            flip_green: cli.green == GreenArg::Down,
            independent_falloff: cli.independent_falloff,
        },
        cube: CubeOptions {
            normal_mapping: !cli.no_normal_map,
        },
    };
    if cli.headless || cli.bench.is_some() {
        run_headless(&cli, scene)
    } else {
        // The key list is printed once the window is up (a failure before prints its error alone).
        run_window(WindowOptions {
            scene_name: cli.scene,
            scene,
            size: cli.size,
            profile: cli.profile.into(),
            frames: cli.frames,
            screenshot: cli.screenshot.clone(),
            msaa: cli.msaa,
        })
        .map_err(anyhow::Error::from)
    }
}

fn run_headless(cli: &Cli, scene: SceneOptions) -> Result<()> {
    let (width, height) = cli.size;
    let mut renderer = HeadlessRenderer::new(&HeadlessOptions {
        scene_name: cli.scene,
        scene,
        width,
        height,
        profile: cli.profile.into(),
        prefer_hardware: cli.prefer_hardware,
        msaa: cli.msaa.into(),
    })?;
    log::info!("{}", renderer.context.info());
    if let Some(k) = cli.bench {
        let times = renderer.bench(k)?;
        let (min, median) = min_median(&times);
        println!(
            "{k} frames at {width}x{height}: min {min:.3} ms/frame, median {median:.3} ms/frame"
        );
    }
    if cli.bench.is_none() || cli.screenshot.is_some() {
        let image = renderer.render_frames(cli.frames.unwrap_or(1))?;
        if let Some(path) = &cli.screenshot {
            save(path, &image)?;
        }
    }
    Ok(())
}

fn save(path: &Path, image: &image::RgbaImage) -> Result<()> {
    write_screenshot(path, image).with_context(|| "cannot save the screenshot".to_string())?;
    log::info!("wrote {}", path.display());
    Ok(())
}
