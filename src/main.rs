//! `tutorial13`: the binary. It parses the command line and prints the error, if any, on one line;
//! the commands are in the library's [`tutorial13::tools`]. The contract (flags, messages, exit
//! status 0, 1 for an error, 2 for a usage error) is `--help` and docs/scenes.md, and
//! tests/all/cli.rs checks it.

use std::ffi::OsString;
use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use tutorial13::scenes::{self, SceneOptions};
use tutorial13::tools::bake::{bake, BakeOptions};
use tutorial13::tools::help;
use tutorial13::tools::make_assets::{make_assets, MakeAssetsOptions};
use tutorial13::tools::normalmap::{normalmap, NormalmapOptions};
use tutorial13::tools::photometric::{photometric, PhotometricOptions};
use tutorial13::tools::run::{run, RunOptions};

#[derive(Parser, Debug)]
#[command(
    name = "tutorial13",
    version,
    about = "opengl-tutorial.org's Tutorial 13 (Normal Mapping), ported to Rust",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    run: RunOptions,
}

#[derive(Subcommand, Debug)]
enum Command {
    MakeAssets(MakeAssetsOptions),
    Bake(BakeOptions),
    Normalmap(NormalmapOptions),
    Photometric(PhotometricOptions),
}

fn main() -> ExitCode {
    keep_freed_memory();
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .format_timestamp(None)
        .format_target(false)
        .init();
    let (cli, scene) = parse();
    let done = match &cli.command {
        None => run(&cli.run, scene),
        Some(Command::MakeAssets(options)) => make_assets(options),
        Some(Command::Bake(options)) => bake(options),
        Some(Command::Normalmap(options)) => normalmap(options),
        Some(Command::Photometric(options)) => photometric(options),
    };
    match done.map_err(anyhow::Error::from) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the error and its causes, outermost first.
            eprintln!("tutorial13: {}", format!("{e:#}").replace('\n', " | "));
            ExitCode::FAILURE
        }
    }
}

/// Asks glibc's malloc to keep what is freed for the next allocation instead of handing it back to
/// the kernel: a 1M-triangle model's first frame builds and drops arrays of tens of megabytes stage
/// after stage, and each fresh mapping costs page faults and zeroing again (BENCHMARKS.md, "A
/// 1M-triangle glTF to its first frame"). Arrays above 32 MiB, glibc's most, are still mapped.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets two of malloc's thresholds; it is called before any thread starts.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, i32::MAX);
    }
}

/// The global flags, and every scene's options (a flag of a scene other than `--scene`'s is an
/// error, printed by clap like any other command-line error).
fn parse() -> (Cli, SceneOptions) {
    let args: Vec<OsString> = std::env::args_os().collect();
    let mut command = help::command_line(Cli::command(), &args);
    let matches = command
        .try_get_matches_from_mut(args)
        .unwrap_or_else(|e| e.exit());
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    let options = SceneOptions {
        assets: cli.run.assets.clone(),
        shaders: cli.run.shaders.clone(),
        ..Default::default()
    };
    let options =
        scenes::scene_options(&matches, cli.run.scene, options).unwrap_or_else(|message| {
            command
                .error(clap::error::ErrorKind::ArgumentConflict, message)
                .exit()
        });
    (cli, options)
}
