//! The documentation against the code: `docs/keys.md` is generated from the scenes' key bindings
//! and must be what the code makes now.

use std::fs;
use std::io::Write;

use tutorial13::frontends::keys_markdown;

use crate::common;

// Fails if docs/keys.md is not exactly what `keys_markdown` makes from the scenes' bindings now: a
// key added, removed or reworded in the code but not in the file, a scene added to SCENES, or the
// file edited by hand. With TUTORIAL13_UPDATE_DOCS=1 it rewrites the file instead (and says so).
#[test]
fn keys_md_matches_the_code() {
    let path = common::manifest().join("docs/keys.md");
    let expected = keys_markdown();
    let actual = fs::read_to_string(&path).unwrap_or_default();
    if std::env::var_os("TUTORIAL13_UPDATE_DOCS").is_some() {
        let said = if actual == expected {
            "is already what the code makes"
        } else {
            fs::write(&path, &expected).unwrap();
            "rewritten from the code"
        };
        let _ = writeln!(
            std::io::stderr(),
            "docs/keys.md {said} (TUTORIAL13_UPDATE_DOCS)"
        );
        return;
    }
    if actual != expected {
        let (line, (old, new)) = actual
            .lines()
            .chain(std::iter::repeat("<end of file>"))
            .zip(expected.lines().chain(std::iter::repeat("<end of text>")))
            .enumerate()
            .find(|(_, (a, e))| a != e)
            .expect("different texts differ in a line");
        panic!(
            "docs/keys.md differs from keys_markdown() from line {}:\n  file: {old}\n  code: {new}\n\
             rewrite it with: TUTORIAL13_UPDATE_DOCS=1 cargo test --release -- docs::",
            line + 1
        );
    }
}
