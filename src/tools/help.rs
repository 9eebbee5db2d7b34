//! `--help` laid out for the terminal: wrapped to its width (at most [`MAX_WIDTH`]), every flag and
//! the scenes' list; `--scene NAME --help` shows that scene's flags alone and its keys instead
//! (every scene's keys would be several screens: docs/keys.md has them).

use std::ffi::OsString;

use clap::Command;

use crate::frontends::keys::key_list;
use crate::scenes::{self, SceneDescriptor, SharedArgs, SCENES};

/// The widest `--help` is laid out, however wide the terminal: longer lines are hard to follow.
pub const MAX_WIDTH: usize = 100;
/// Where the text of a row of the scenes' and keys' lists starts ("  " and a 15-column name).
const ROW_INDENT: usize = 18;

/// `command` (the global flags and the tools) with every scene's flags ([`scenes::command_line`]),
/// laid out for [`help_width`]. Its help ends with the scenes' list, or, when `args` (the
/// program's, its name first) ask for help with `--scene NAME`, shows only the flags that scene
/// reads and ends with its keys.
pub fn command_line(command: Command, args: &[OsString]) -> Command {
    let width = help_width();
    let command = scenes::command_line(command).term_width(width);
    match scene_help_asked(args) {
        Some(scene) => only_flags_of(command, scene).after_help(scene_keys(scene, width)),
        None => command.after_help(scene_list(width)),
    }
}

/// The width `--help` is laid out for, found as clap's `wrap_help` finds it: the terminal's (of
/// stdout, stderr or stdin, the first that is one), else `COLUMNS` (which a pipe or a test sets),
/// else [`MAX_WIDTH`]; never more than [`MAX_WIDTH`].
pub fn help_width() -> usize {
    let terminal = terminal_size::terminal_size().map(|(w, _)| usize::from(w.0));
    let columns = || std::env::var("COLUMNS").ok()?.parse().ok();
    terminal
        .or_else(columns)
        .filter(|&w| w > 0)
        .map_or(MAX_WIDTH, |w| w.min(MAX_WIDTH))
}

/// The scene `--scene NAME` (or `--scene=NAME`) names when `args` also hold `-h` or `--help`
/// before any `--`. Read before clap parses: clap prints the help while it parses, before the
/// scene is known.
fn scene_help_asked(args: &[OsString]) -> Option<&'static SceneDescriptor> {
    let args: Vec<&str> = args
        .iter()
        .skip(1)
        .map_while(|a| a.to_str())
        .take_while(|a| *a != "--")
        .collect();
    if !args.iter().any(|a| matches!(*a, "-h" | "--help")) {
        return None;
    }
    let name = args.windows(2).find(|w| w[0] == "--scene").map(|w| w[1]);
    let name = name.or_else(|| args.iter().find_map(|a| a.strip_prefix("--scene=")))?;
    scenes::find(name).ok()
}

/// `command` with the flags `scene` does not read hidden from its help (still parsed: giving one
/// is the error [`scenes::scene_options`] reports).
fn only_flags_of(command: Command, scene: &SceneDescriptor) -> Command {
    let shared = <SharedArgs as clap::Args>::augment_args(Command::new("shared"));
    let others = SCENES
        .iter()
        .filter(|other| ***other != *scene)
        .map(|other| (other.args)(Command::new(other.name)));
    let mut hidden: Vec<String> = shared
        .get_arguments()
        .map(|arg| arg.get_id().to_string())
        .filter(|id| !scene.reads_shared(id))
        .collect();
    for other in others {
        hidden.extend(other.get_arguments().map(|arg| arg.get_id().to_string()));
    }
    hidden.iter().fold(command, |command, id| {
        command.mut_arg(id, |arg| arg.hide(true))
    })
}

/// `--help`'s closing text: the scenes, and where their keys are.
fn scene_list(width: usize) -> String {
    let mut text = String::from("Scenes (--scene NAME):");
    for scene in SCENES {
        let row = format!("  {:<15} {}", scene.name, scene.description);
        text.push_str(&format!("\n{}", wrap_row(&row, width)));
    }
    text.push_str(&format!(
        "\n\n{}",
        wrap(
            "Keys in the window: `--scene NAME --help` lists a scene's (and only its flags); \
             docs/keys.md has every scene's.",
            width,
            0
        )
    ));
    text
}

/// `--scene NAME --help`'s closing text: the scene's keys, as the window prints them.
fn scene_keys(scene: &'static SceneDescriptor, width: usize) -> String {
    let keys: Vec<String> = key_list(scene)
        .lines()
        .map(|row| wrap_row(row, width))
        .collect();
    let others = "The other scenes' flags: --help without --scene; their keys: docs/keys.md.";
    format!("{}\n\n{}", keys.join("\n"), wrap(others, width, 0))
}

/// A row of a list (a name, then its text from [`ROW_INDENT`]) wrapped to `width`, its text's
/// later lines under its text rather than its name. (clap wraps the closing text too, but from the
/// first column.)
fn wrap_row(row: &str, width: usize) -> String {
    wrap(row, width, ROW_INDENT)
}

/// `text` broken at spaces into lines of at most `width` columns (a longer word stands alone), the
/// lines after the first indented by `indent`.
fn wrap(text: &str, width: usize, indent: usize) -> String {
    let columns = |s: &str| s.chars().count();
    let words = text.trim_start_matches(' ');
    let mut lines = vec![text[..text.len() - words.len()].to_string()];
    // Split at each space, so that the padding after a name is kept.
    for word in words.split(' ') {
        let line = lines.last_mut().expect("one line at least");
        if line.trim().is_empty() {
            line.push_str(word);
        } else if columns(line) + 1 + columns(word) > width {
            lines.push(format!("{:indent$}{word}", ""));
        } else {
            line.push(' ');
            line.push_str(word);
        }
    }
    let lines: Vec<&str> = lines.iter().map(|line| line.trim_end()).collect();
    lines.join("\n")
}
