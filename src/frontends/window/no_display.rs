//! The window's one message that suggests a command: where there is no display, the headless
//! command that works there, as the user runs the program from where they are ([`invocation`]).

/// The message for a machine without a display, with the command that works there, as the user
/// runs it from where they are (see [`invocation`]).
pub fn no_display_message(reason: &str) -> String {
    format!(
        "no display to open a window on ({}); render without one: \
         {} --headless --frames 1 --screenshot frame.png",
        without_source_location(reason),
        invocation()
    )
}

/// winit's OS errors read "os error at /home/.../winit-0.30/src/...rs:788: Failed to open ...": the
/// user needs the reason, not where in winit's source it was raised.
pub fn without_source_location(reason: &str) -> String {
    const MARK: &str = "os error at ";
    match reason.find(MARK) {
        Some(start) => match reason[start + MARK.len()..].find(": ") {
            Some(end) => {
                let rest = &reason[start + MARK.len() + end + 2..];
                format!("{}{rest}", &reason[..start])
            }
            None => reason.to_string(),
        },
        None => reason.to_string(),
    }
}

/// How the user runs this program from where they are, for the commands its messages suggest:
/// `cargo run --release --` when the binary is the one cargo built in a crate's target folder (a
/// clone, where it is not on PATH), else its name.
pub fn invocation() -> String {
    invocation_for(std::env::current_exe().ok().as_deref())
}

/// [`invocation`] for a binary at `exe`.
pub fn invocation_for(exe: Option<&std::path::Path>) -> String {
    let folder = |p: &std::path::Path, up: usize| {
        p.ancestors()
            .nth(up)
            .and_then(|d| d.file_name())
            .and_then(|n| n.to_str())
            .map(str::to_owned)
    };
    let Some(exe) = exe else {
        return "tutorial13".into();
    };
    match (folder(exe, 1).as_deref(), folder(exe, 2).as_deref()) {
        (Some("release"), Some("target")) => "cargo run --release --".into(),
        (Some("debug"), Some("target")) => "cargo run --".into(),
        _ => "tutorial13".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a message suggests `tutorial13 ...` to a user who runs the binary cargo built in a
    // clone (not on PATH), or `cargo run` to one who installed it.
    #[test]
    fn suggested_commands_run_from_where_the_user_is() {
        use std::path::Path;
        let at = |p: &str| invocation_for(Some(Path::new(p)));
        assert_eq!(
            at("/home/l/tutorial13/target/release/tutorial13"),
            "cargo run --release --"
        );
        assert_eq!(
            at("/home/l/tutorial13/target/debug/tutorial13"),
            "cargo run --"
        );
        assert_eq!(at("/usr/local/bin/tutorial13"), "tutorial13");
        assert_eq!(at("/opt/release/tutorial13"), "tutorial13");
        assert_eq!(invocation_for(None), "tutorial13");
    }

    // Fails if winit's source path reaches the user's error line, or if other reasons are altered.
    #[test]
    fn display_errors_drop_winits_source_path() {
        let winit =
            "os error at /root/.cargo/registry/src/x/winit-0.30.13/src/platform_impl/linux/\
                     mod.rs:788: Failed to open connection to X server";
        let message = no_display_message(winit);
        assert!(
            message.contains("(Failed to open connection to X server)"),
            "{message}"
        );
        assert!(
            !message.contains(".rs:") && !message.contains("cargo"),
            "{message}"
        );
        let plain = "neither DISPLAY nor WAYLAND_DISPLAY is set";
        assert!(no_display_message(plain).contains(&format!("({plain})")));
    }
}
