//! The documentation against the code. `docs/keys.md` and the README's list of scenes are generated
//! from the scenes' descriptors and must be what the code makes now; every relative link in the
//! README, BENCHMARKS.md and docs/*.md points at a file (and heading) that exists; the README's
//! short list of differences from the C++ names every one that docs/differences.md details; the
//! Rust names those documents mention are defined in the code; and no tracked text file cites an
//! issue by its number, which a reader of the repository cannot look up.
//!
//! What the name check does, and what it does not (it reads text; it does not compile anything):
//! - It reads every `.rs` file under src/, tests/, benches/ and fuzz/ with comments,
//!   strings and character literals blanked out, and records the names defined there: `fn`,
//!   `struct`, `enum`, `union`, `trait`, `const`, `static`, `type` and `mod` items, the named fields
//!   of structs and the variants of enums, and, for the `fn`, `const` and `type` items of an `impl`
//!   or `trait` block, `Owner::name` (the owner is the last segment of the implemented type's path,
//!   generics left out, so `impl Trait for a::Foo<T>` gives `Foo::name`).
//! - In the documents it looks at text in single backticks outside fenced code blocks, and
//!   skips table columns headed "C++…" or "#" (those name the C++ original's code). A span is taken
//!   as a Rust name when, after a trailing `(…)` and a turbofish `::<…>` are dropped, it is a path
//!   of identifiers (`a::b::C::d`) or one identifier in Rust's styles for items: snake_case with an
//!   underscore (`load_mesh`), UpperCamelCase (`SceneDescriptor`) or SCREAMING_CASE of two letters or
//!   more (`LIGHT_POS`). Not checked: single lower-case words (`draw`, `tutorial`: too often plain
//!   English or a scene's name), lowerCamelCase (`glfwInit`: the C++ and GLSL names), and paths
//!   starting with another crate's or library's name (`glow::`, `glm::`, `std::`, …).
//! - A path `a::b::Name` or `a::b::Type::member`: the leading lower-case segments are modules, and
//!   each must have its file (`a.rs` or `a/mod.rs`, from src/, tests/all/, benches/ or fuzz/;
//!   a leading `crate::` or `tutorial13::` is dropped). `Name` must be defined in that
//!   module's file or folder, or named in the module's file (a `pub use`). `Type` must be a struct,
//!   enum, union, trait or type alias and `Type::member` one of its recorded members (a method or
//!   associated item of an `impl`/`trait` block, a field or a variant). Not checked: that the item
//!   is public, that a method is in the `impl` of this very `Type` rather than of another type of
//!   the same name, or that anything type-checks.
//! - A single identifier must be defined somewhere in the code, or be a word of a shader in
//!   shaders/ (the GLSL uniforms the guide names), or be one of [`OTHER_CRATES`], which must at
//!   least still be used in src/. A name starting `GL_` or `GLFW_` that the code does not define is
//!   OpenGL's or GLFW's: it must occur in src/'s text (code or comments).
//! - A backticked relative path into the repository's own folders (`tests/all/render.rs`,
//!   `shaders/Sprite.*`) must exist (a trailing `*` matches any file starting with the rest).
//! - A Rust name tied to a `.rs` file by a link must be defined in that very file. The forms are a
//!   span followed by ` ([text](file.rs))` or by ` in [text](file.rs)`, and a link whose text is
//!   the span alone, ``[`name`](file.rs)``; the file is the link's target (without its `#anchor`)
//!   from the document's folder. A leading module path is dropped (`pipeline::obj_parse::load_obj_threaded`
//!   is `load_obj_threaded`); a single name must be an item, field or variant of that file, and
//!   `Type::member` a method or associated item of an `impl`/`trait` block in that file, or a field
//!   or variant declared there. Not checked: a name a few words before its link, or a name defined
//!   in a submodule of the `mod.rs` linked to.

use std::collections::{HashMap, HashSet};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

use tutorial13::frontends::keys::{key_rows, FrontEnd};
use tutorial13::scenes::SCENES;

use crate::common;

/// The markdown files at the top of the repository whose links and names are checked, besides every
/// `docs/*.md` (see [`markdown_docs`]).
const TOP_DOCS: &[&str] = &["README.md", "BENCHMARKS.md"];

/// The lines around the README's list of scenes (the start marker is the beginning of a line).
const README_LIST_START: &str = "<!-- The list below is generated from SCENES";
const README_LIST_END: &str = "<!-- End of the generated list. -->";

/// The lines around docs/reading-guide.md's table of the tutorial's sections, made from the tour.
const GUIDE_TABLE_START: &str = "<!-- The table below is generated from the tour";
const GUIDE_TABLE_END: &str = "<!-- End of the generated table. -->";

/// The heading of the README's short list of differences from the C++ original.
const README_DIFFERENCES: &str = "## Where this port deliberately differs from the C++ original";

/// docs/differences.md's headings that group differences rather than name one.
const DIFFERENCE_GROUPS: &[&str] = &["and-from-the-articles-code"];

/// Where the code is read from.
const CODE_DIRS: &[&str] = &["src", "tests", "benches", "fuzz"];

/// Where a module path starts.
const MODULE_ROOTS: &[&str] = &["src", "tests/all", "benches", "fuzz"];

/// Folders of this repository that a backticked path may point into.
const REPO_DIRS: &[&str] = &[
    "src/", "tests/", "benches/", "fuzz/", "shaders/", "docs/", "assets/", ".ci/",
];

/// Paths under these names belong to other crates or libraries (or the C++ original's GLM) and are
/// not looked up.
const FOREIGN_PREFIXES: &[&str] = &[
    "glow",
    "glam",
    "glm",
    "glutin",
    "winit",
    "std",
    "core",
    "clap",
    "tobj",
    "image",
    "mikktspace",
    "egui",
];

/// Names from other crates that the documents mention as the code's own calls: each must still
/// occur in src/ (so a name the code stopped using is still caught), but is not looked up.
const OTHER_CRATES: &[(&str, &str)] = &[
    ("Drop", "std"),
    ("Default", "std"),
    ("Mat3::from_mat4", "glam"),
    ("Version::new", "glutin"),
    ("from_loader_function_cstr", "glow"),
    ("run_app", "winit"),
    ("RedrawRequested", "winit"),
    ("KeyCode::Escape", "winit"),
    ("WindowEvent::CloseRequested", "winit"),
];

/// `docs/keys.md`: every scene of `SCENES`, in their order, with its description and a table of
/// the rows `key_list` prints for it (the window's). [`keys_md_matches_the_code`] fails when the
/// committed file differs from this.
pub fn keys_markdown() -> String {
    let cell = |text: &str| text.replace('|', "\\|");
    let mut text = String::from(
        "# Keys, scene by scene\n\n\
         *Generated from the scenes' key bindings by `keys_markdown` (tests/all/docs.rs); do not \
         edit: the test `docs::keys_md_matches_the_code` (tests/all/docs.rs) fails when this file \
         differs, and rewrites it when run with `TUTORIAL13_UPDATE_DOCS=1`.*\n\n\
         The window prints the same list when a scene starts, and `--scene NAME --help` prints that scene's.\n",
    );
    for scene in SCENES {
        text.push_str(&format!(
            "\n## {}\n\n`--scene {}`: {}\n\n| key | does |\n|---|---|\n",
            scene.name,
            scene.name,
            cell(scene.description)
        ));
        for (key, help) in key_rows(scene, FrontEnd::Window) {
            text.push_str(&format!("| {} | {} |\n", cell(&key), cell(help)));
        }
    }
    text
}

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

// Fails if the README's list of scenes (between its two marker lines) is not one line per scene of
// SCENES, in their order, each the scene's name and its descriptor's description word for word.
// With TUTORIAL13_UPDATE_DOCS=1 it rewrites the list instead (and says so).
#[test]
fn readme_scene_list_matches_the_code() {
    let expected: String = SCENES
        .iter()
        .map(|scene| format!("- `{}`: {}\n", scene.name, scene.description))
        .collect();
    check_generated(
        "README.md",
        (README_LIST_START, README_LIST_END),
        &expected,
        "scene list",
        "SCENES'",
    );
}

// Fails if docs/reading-guide.md's table of the tutorial's sections is not exactly what the tour
// makes now (`tour::reading_guide_table`): a step, a caption's section, a C++ range or a Rust item
// changed, moved or renamed in the code (its lines linked move with it) but not in the guide, or the
// table edited by hand; so the map in the guide and the tour's cannot drift. With
// TUTORIAL13_UPDATE_DOCS=1 it rewrites the table instead.
#[test]
fn reading_guide_section_table_is_the_tours() {
    check_generated(
        "docs/reading-guide.md",
        (GUIDE_TABLE_START, GUIDE_TABLE_END),
        &tutorial13::tour::reading_guide_table(),
        "table of the tutorial's sections",
        "the tour's (src/tour/steps.rs)",
    );
}

/// Checks that the text of `doc` between the line starting `markers.0` and `markers.1` is
/// `expected`, or rewrites it under TUTORIAL13_UPDATE_DOCS; `what` and `whose` name it in messages.
fn check_generated(doc: &str, markers: (&str, &str), expected: &str, what: &str, whose: &str) {
    let path = common::manifest().join(doc);
    let text = read(doc);
    let start = text
        .find(markers.0)
        .and_then(|i| text[i..].find('\n').map(|n| i + n + 1))
        .unwrap_or_else(|| panic!("{doc} has no start marker for its {what}"));
    let end = start
        + text[start..]
            .find(markers.1)
            .unwrap_or_else(|| panic!("{doc} has no end marker for its {what}"));
    if std::env::var_os("TUTORIAL13_UPDATE_DOCS").is_some() {
        let said = if text[start..end] == *expected {
            "is already what the code makes"
        } else {
            let updated = format!("{}{expected}{}", &text[..start], &text[end..]);
            fs::write(&path, updated).unwrap();
            "rewritten from the code"
        };
        let _ = writeln!(
            std::io::stderr(),
            "{doc}'s {what} {said} (TUTORIAL13_UPDATE_DOCS)"
        );
        return;
    }
    assert_eq!(
        text[start..end],
        *expected,
        "{doc}'s {what} is not {whose}; rewrite it with: TUTORIAL13_UPDATE_DOCS=1 cargo test \
         --release -- docs::"
    );
}

// Fails if a relative link in README.md, BENCHMARKS.md or docs/*.md points at a file that does not
// exist, or at a heading (#anchor) that the linked markdown file (or the same file) does not have.
#[test]
fn links_point_at_files_that_exist() {
    let mut broken = Vec::new();
    for doc in &markdown_docs() {
        let doc = doc.as_str();
        let text = read(doc);
        let folder = Path::new(doc).parent().unwrap();
        for target in links(&text) {
            if target.starts_with("http://")
                || target.starts_with("https://")
                || target.starts_with("mailto:")
            {
                continue;
            }
            let (file, anchor) = match target.split_once('#') {
                Some((file, anchor)) => (file, Some(anchor)),
                None => (target.as_str(), None),
            };
            let path = if file.is_empty() {
                PathBuf::from(doc)
            } else {
                normalize(&folder.join(file))
            };
            if !common::manifest().join(&path).exists() {
                broken.push(format!("{doc}: ({target}): no file {}", path.display()));
                continue;
            }
            if let Some(anchor) = anchor.filter(|_| path.extension().is_some_and(|e| e == "md")) {
                let headings = heading_slugs(&read(path.to_str().unwrap()));
                if !headings.contains(anchor) {
                    broken.push(format!("{doc}: ({target}): no such heading"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

// Fails if README.md, BENCHMARKS.md or a docs/*.md page names, in backticks, a Rust item that the
// code does not define (renamed, moved to another module, or removed), a `Type::member` that the
// type does not have, a module path without its file, or a path into the repository that does not
// exist. What counts as a Rust name, and what is not checked, is in this file's module
// documentation.
#[test]
fn named_rust_items_exist() {
    let index = Index::read();
    let mut missing = Vec::new();
    for doc in &markdown_docs() {
        for span in code_spans(&read(doc)) {
            if let Err(why) = index.check(&span) {
                missing.push(format!("{doc}: `{span}`: {why}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "names in the documents that the code does not have:\n{}",
        missing.join("\n")
    );
}

// Fails if README.md, BENCHMARKS.md or a docs/*.md page ties a Rust name to a source file by a link
// (`load_mesh` ([tutorial13.rs](…)), `load_mesh` in [tutorial13.rs](…), or [`load_mesh`](…)) and
// that file does not define it: the name moved to another file, or the link was wrong from the
// start.
#[test]
fn names_linked_to_a_file_are_defined_there() {
    let index = Index::read();
    let mut misplaced = Vec::new();
    for doc in &markdown_docs() {
        let folder = Path::new(doc).parent().unwrap();
        for (span, target) in linked_names(&read(doc)) {
            let file = normalize(&folder.join(&target));
            if file.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let Some(name) = rust_name(span.trim()) else {
                continue;
            };
            if let Err(why) = index.defined_in(&name, &file) {
                misplaced.push(format!("{doc}: `{span}` linked to {target}: {why}"));
            }
        }
    }
    assert!(
        misplaced.is_empty(),
        "names linked to a source file that does not define them:\n{}",
        misplaced.join("\n")
    );
}

// Fails if a difference that docs/differences.md details (one of its headings) has no line in the
// README's short list linking to it: the README's list must name every difference, and say it in
// one line, the details being written once, on that page.
#[test]
fn readme_lists_every_difference() {
    let readme = read("README.md");
    let start = readme
        .find(README_DIFFERENCES)
        .expect("README.md has no section on the differences from the C++ original");
    let section = &readme[start + README_DIFFERENCES.len()..];
    let section = &section[..section.find("\n## ").unwrap_or(section.len())];
    let linked: HashSet<String> = links(section)
        .iter()
        .filter_map(|target| target.strip_prefix("docs/differences.md#"))
        .map(String::from)
        .collect();
    let details = read("docs/differences.md");
    let mut unlisted: Vec<String> = prose(&details)
        .filter(|line| line.starts_with("##"))
        .flat_map(heading_slugs)
        .filter(|slug| !DIFFERENCE_GROUPS.contains(&slug.as_str()) && !linked.contains(slug))
        .collect();
    unlisted.sort();
    assert!(
        unlisted.is_empty(),
        "differences in docs/differences.md that the README's list does not link to:\n{}",
        unlisted.join("\n")
    );
}

// Fails if a tracked `.rs`, `.md` or `.toml` file, or .ci/run, cites an issue by its number
// ("issue" or "issues", any case, then a number, maybe after `#`): a reader of the repository cannot
// look the issue up, so the text must say the fact itself.
#[test]
fn no_file_cites_an_issue_number() {
    let cited = |n: &str| format!("see Issue{n} here");
    assert!(cites_issue(&cited(" 8")) && cites_issue(&cited(" #17")));
    assert!(cites_issue(&cited("s 8 and 19")) && !cites_issue(&cited("'s target")));
    assert!(!cites_issue("a tissue 5 cm wide"));
    let mut citing = Vec::new();
    for file in text_files() {
        let Ok(text) = fs::read_to_string(common::manifest().join(&file)) else {
            continue;
        };
        for (number, line) in text.lines().enumerate() {
            if cites_issue(line) {
                citing.push(format!(
                    "{}:{}: {}",
                    file.display(),
                    number + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(
        citing.is_empty(),
        "lines that cite an issue by number (say the fact instead):\n{}",
        citing.join("\n")
    );
}

/// Whether `line` has the word "issue" or "issues" (any case) followed by a number, maybe after
/// spaces, `#`, `-` or `_`.
fn cites_issue(line: &str) -> bool {
    let lower = line.to_ascii_lowercase();
    lower.match_indices("issue").any(|(i, word)| {
        let starts_word = !lower[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_');
        let after = &lower[i + word.len()..];
        let after = after.strip_prefix('s').unwrap_or(after);
        let number = after.trim_start_matches([' ', '\t', '#', '-', '_']);
        starts_word && number.starts_with(|c: char| c.is_ascii_digit())
    })
}

/// The repository's `.rs`, `.md` and `.toml` files and .ci/run: git's list of tracked files, or,
/// where git cannot give one (a copy without .git), every such file outside `target/` and hidden
/// folders other than `.ci/`.
fn text_files() -> Vec<PathBuf> {
    let text = |path: &Path| {
        path == Path::new(".ci/run")
            || path
                .extension()
                .is_some_and(|e| e == "rs" || e == "md" || e == "toml")
    };
    let root = common::manifest();
    let listed = Command::new("git")
        .args(["ls-files", "-z"])
        .current_dir(root)
        .output()
        .ok()
        .filter(|out| out.status.success());
    let files: Vec<PathBuf> = match listed {
        Some(out) => String::from_utf8_lossy(&out.stdout)
            .split('\0')
            .filter(|f| !f.is_empty())
            .map(PathBuf::from)
            .collect(),
        None => {
            let mut files = Vec::new();
            let mut folders = vec![PathBuf::new()];
            while let Some(folder) = folders.pop() {
                for entry in fs::read_dir(root.join(&folder)).unwrap().flatten() {
                    let path = folder.join(entry.file_name());
                    let name = entry.file_name().to_string_lossy().into_owned();
                    if !entry.path().is_dir() {
                        files.push(path);
                    } else if name == ".ci"
                        || !(name.starts_with('.') || path == Path::new("target"))
                    {
                        folders.push(path);
                    }
                }
            }
            files
        }
    };
    let mut files: Vec<PathBuf> = files.into_iter().filter(|f| text(f)).collect();
    files.sort();
    assert!(
        files.iter().any(|f| f == Path::new("README.md")),
        "found no README.md among the repository's files"
    );
    files
}

/// README.md, BENCHMARKS.md and every `docs/*.md`, relative to the crate.
fn markdown_docs() -> Vec<String> {
    let mut docs: Vec<String> = common::files_under(&common::manifest().join("docs"))
        .into_iter()
        .filter(|f| f.parent() == Some(Path::new("")) && f.extension().is_some_and(|e| e == "md"))
        .map(|f| format!("docs/{}", f.display()))
        .collect();
    docs.sort();
    TOP_DOCS.iter().map(|d| d.to_string()).chain(docs).collect()
}

fn read(path: &str) -> String {
    let full = common::manifest().join(path);
    fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}", full.display()))
}

/// `a/b/../c` → `a/c` (the path need not exist).
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// Markdown outside fenced code blocks, line by line.
fn prose(text: &str) -> impl Iterator<Item = &str> {
    let mut fenced = false;
    text.lines().filter(move |line| {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            return false;
        }
        !fenced
    })
}

/// The targets of inline links and images, `[text](target)`.
fn links(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    for line in prose(text) {
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            rest = &rest[i + 2..];
            if let Some(end) = rest.find(')') {
                targets.push(rest[..end].trim().to_string());
                rest = &rest[end..];
            }
        }
    }
    targets
}

/// The backticked spans that a link ties to a file (see the module documentation), each with the
/// link's target as written, without its `#anchor`.
fn linked_names(text: &str) -> Vec<(String, String)> {
    let mut found = Vec::new();
    for line in prose(text) {
        let ticks: Vec<usize> = line.match_indices('`').map(|(i, _)| i).collect();
        for pair in ticks.chunks_exact(2) {
            let (open, close) = (pair[0], pair[1]);
            let after = &line[close + 1..];
            let target = if line[..open].ends_with('[') {
                // [`name`](target)
                after
                    .strip_prefix("](")
                    .and_then(|rest| rest.split_once(')'))
                    .map(|(target, _)| target)
            } else {
                // `name` ([text](target))  or  `name` in [text](target)
                after
                    .strip_prefix(" (")
                    .or_else(|| after.strip_prefix(" in "))
                    .and_then(link_target)
            };
            if let Some(target) = target {
                let file = target.split_once('#').map_or(target, |(file, _)| file);
                found.push((line[open + 1..close].to_string(), file.trim().to_string()));
            }
        }
    }
    found
}

/// The target of the link `[text](target)` that `text` starts with.
fn link_target(text: &str) -> Option<&str> {
    let (label, rest) = text.strip_prefix('[')?.split_once("](")?;
    if label.contains(']') {
        return None;
    }
    rest.split_once(')').map(|(target, _)| target)
}

/// GitHub's anchors for a file's headings: lower case, punctuation other than `-` and `_` dropped,
/// spaces turned into `-`.
fn heading_slugs(text: &str) -> HashSet<String> {
    prose(text)
        .filter_map(|line| line.strip_prefix('#'))
        .map(|heading| {
            heading
                .trim_start_matches('#')
                .trim()
                .to_lowercase()
                .chars()
                .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
                .map(|c| if c == ' ' { '-' } else { c })
                .collect()
        })
        .collect()
}

/// The backticked spans of the prose, leaving out table cells in columns headed "C++…" or "#".
fn code_spans(text: &str) -> Vec<String> {
    let mut spans = Vec::new();
    let mut skipped_columns: Vec<usize> = Vec::new();
    let mut in_table = false;
    for line in prose(text) {
        let cells: Vec<String> = if line.trim_start().starts_with('|') {
            let line = line.replace("\\|", "\u{1}");
            line.trim()
                .trim_matches('|')
                .split('|')
                .map(|cell| cell.replace('\u{1}', "|"))
                .collect()
        } else {
            in_table = false;
            vec![line.to_string()]
        };
        if line.trim_start().starts_with('|') && !in_table {
            // A table's first row is its header.
            in_table = true;
            skipped_columns = cells
                .iter()
                .enumerate()
                .filter(|(_, c)| {
                    let c = c.trim();
                    c.starts_with("C++") || c == "#"
                })
                .map(|(i, _)| i)
                .collect();
            continue;
        }
        for (i, cell) in cells.iter().enumerate() {
            if in_table && skipped_columns.contains(&i) {
                continue;
            }
            let mut parts = cell.split('`');
            parts.next();
            while let (Some(span), Some(_)) = (parts.next(), parts.next()) {
                spans.push(span.to_string());
            }
        }
    }
    spans
}

fn is_ident(s: &str) -> bool {
    let mut chars = s.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn is_snake(s: &str) -> bool {
    s.contains('_')
        && s.starts_with(|c: char| c.is_ascii_lowercase())
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

fn is_upper_camel(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_uppercase())
        && s.chars().any(|c| c.is_ascii_lowercase())
        && s.chars().all(|c| c.is_ascii_alphanumeric())
}

fn is_screaming(s: &str) -> bool {
    s.len() >= 2
        && s.starts_with(|c: char| c.is_ascii_uppercase())
        && s.chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

/// Records that `file` defines `key`.
fn record(map: &mut HashMap<String, Vec<PathBuf>>, key: String, file: &Path) {
    let files = map.entry(key).or_default();
    if !files.iter().any(|f| f == file) {
        files.push(file.to_path_buf());
    }
}

/// The names the code defines (see the module documentation).
struct Index {
    /// Name → the files (relative to the crate) that define it.
    names: HashMap<String, Vec<PathBuf>>,
    /// Struct, enum, union, trait and type-alias names.
    types: HashSet<String>,
    /// `Owner::member` (methods and associated items of `impl`/`trait` blocks, fields, variants) →
    /// the files that define it.
    members: HashMap<String, Vec<PathBuf>>,
    /// Every word of every shader.
    glsl_words: HashSet<String>,
    /// src/'s text as it is (comments included), for [`OTHER_CRATES`].
    src_text: String,
}

impl Index {
    fn read() -> Self {
        let mut index = Index {
            names: HashMap::new(),
            types: HashSet::new(),
            members: HashMap::new(),
            glsl_words: HashSet::new(),
            src_text: String::new(),
        };
        let root = common::manifest();
        for dir in CODE_DIRS {
            for file in common::files_under(&root.join(dir)) {
                if file.extension().is_some_and(|e| e == "rs") {
                    let relative = Path::new(dir).join(file);
                    let text = fs::read_to_string(root.join(&relative)).unwrap();
                    if relative.starts_with("src") {
                        index.src_text.push_str(&text);
                    }
                    index.add_file(&relative, &text);
                }
            }
        }
        for file in common::files_under(&root.join("shaders")) {
            let text = fs::read_to_string(root.join("shaders").join(file)).unwrap();
            let words = text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'));
            index
                .glsl_words
                .extend(words.filter(|w| !w.is_empty()).map(String::from));
        }
        index
    }

    fn define(&mut self, name: &str, file: &Path) {
        record(&mut self.names, name.to_string(), file);
    }

    /// `owner::name`, defined in `file`.
    fn define_member(&mut self, owner: &str, name: &str, file: &Path) {
        record(&mut self.members, format!("{owner}::{name}"), file);
    }

    /// Records what one file defines, reading its tokens with a stack of `{ }` scopes.
    fn add_file(&mut self, file: &Path, text: &str) {
        #[derive(Clone, PartialEq)]
        enum Owner {
            Struct(String),
            Enum(String),
            /// `impl` and `trait` blocks: their items are members of the type.
            Items(String),
            Other,
        }
        let tokens = tokens(&tutorial13::tour::excerpt::code_only(text));
        let tok = |i: usize| tokens.get(i).map(String::as_str).unwrap_or("");
        // Each open `{`: who owns it, and the `(`/`[` depth inside it.
        let mut scopes: Vec<(Owner, i32)> = vec![(Owner::Other, 0)];
        let mut pending = Owner::Other;
        let mut i = 0;
        while i < tokens.len() {
            let t = tok(i);
            let (owner, depth) = scopes.last().cloned().unwrap();
            match t {
                "struct" | "union" | "enum" | "trait" if is_ident(tok(i + 1)) => {
                    let name = tok(i + 1).to_string();
                    self.define(&name, file);
                    self.types.insert(name.clone());
                    pending = match t {
                        "enum" => Owner::Enum(name),
                        "trait" => Owner::Items(name),
                        _ => Owner::Struct(name),
                    };
                    i += 1;
                }
                "fn" | "mod" | "const" | "static" | "type"
                    if is_ident(tok(i + 1))
                        && !matches!(tok(i + 1), "fn" | "unsafe" | "extern" | "async" | "_") =>
                {
                    let name = tok(i + 1);
                    self.define(name, file);
                    if t == "type" {
                        self.types.insert(name.to_string());
                    }
                    if let (Owner::Items(ty), "fn" | "const" | "type") = (&owner, t) {
                        if depth == 0 {
                            self.define_member(ty, name, file);
                        }
                    }
                    pending = Owner::Other;
                    i += 1;
                }
                // An `impl` block (not `impl Trait` in a signature): it starts an item.
                "impl"
                    if depth == 0
                        && matches!(
                            tok(i.wrapping_sub(1)),
                            "" | "}" | ";" | "]" | "{" | "unsafe"
                        ) =>
                {
                    // impl<…> Trait<…> for path::Type<…> { … }  or  impl<…> path::Type<…> { … }:
                    // the owner is the last identifier outside `<…>` (after `for`, if any).
                    let mut j = i + 1;
                    let mut angle = 0;
                    let mut owner = String::new();
                    while j < tokens.len() && !matches!(tok(j), "{" | ";" | "where") {
                        match tok(j) {
                            "<" => angle += 1,
                            ">" => angle -= 1,
                            "for" if angle == 0 => owner.clear(),
                            "dyn" => {}
                            w if angle == 0 && is_ident(w) => owner = w.to_string(),
                            _ => {}
                        }
                        j += 1;
                    }
                    pending = Owner::Items(owner);
                    i = j - 1;
                }
                "{" => {
                    scopes.push((std::mem::replace(&mut pending, Owner::Other), 0));
                }
                "}" => {
                    scopes.pop();
                    if scopes.is_empty() {
                        scopes.push((Owner::Other, 0));
                    }
                }
                ";" if depth == 0 => pending = Owner::Other,
                "(" | "[" => scopes.last_mut().unwrap().1 += 1,
                ")" | "]" => scopes.last_mut().unwrap().1 -= 1,
                name if is_ident(name) && depth == 0 => {
                    let after_separator = matches!(tok(i.wrapping_sub(1)), "{" | "," | "]");
                    match &owner {
                        Owner::Struct(ty)
                            if tok(i + 1) == ":"
                                && (after_separator
                                    || matches!(tok(i.wrapping_sub(1)), "pub" | ")"))
                                && name != "pub" =>
                        {
                            self.define(name, file);
                            self.define_member(ty, name, file);
                        }
                        Owner::Enum(ty)
                            if after_separator
                                && matches!(tok(i + 1), "," | "(" | "{" | "=" | "}") =>
                        {
                            self.define(name, file);
                            self.define_member(ty, name, file);
                        }
                        _ => {}
                    }
                }
                _ => {}
            }
            i += 1;
        }
    }

    /// Whether a backticked span names something the code has (`Ok` also when the span is not taken
    /// as a Rust name at all).
    fn check(&self, span: &str) -> Result<(), String> {
        let span = span.trim();
        if let Some(path) = self.repo_path(span) {
            return path;
        }
        let name = rust_name(span);
        let Some(name) = name else { return Ok(()) };
        if let Some((_, whose)) = OTHER_CRATES.iter().find(|(n, _)| *n == name) {
            return match self.src_text.contains(&name) {
                true => Ok(()),
                false => Err(format!("{whose}'s, and src/ does not use it any more")),
            };
        }
        let opengl = name.starts_with("GL_") || name.starts_with("GLFW_");
        if opengl && !self.names.contains_key(&name) {
            return match self.src_text.contains(&name) {
                true => Ok(()),
                false => Err("an OpenGL or GLFW name that src/ neither uses nor mentions".into()),
            };
        }
        let segments: Vec<&str> = name.split("::").collect();
        if segments.len() == 1 {
            return match self.names.contains_key(&name) || self.glsl_words.contains(&name) {
                true => Ok(()),
                false => Err("defined nowhere in the code or the shaders".into()),
            };
        }
        let segments = match segments[0] {
            "crate" | "tutorial13" | "self" => &segments[1..],
            _ => &segments[..],
        };
        let modules = segments[..segments.len() - 1]
            .iter()
            .take_while(|s| s.starts_with(|c: char| c.is_ascii_lowercase()))
            .count();
        let (modules, items) = segments.split_at(modules);
        let region = if modules.is_empty() {
            None
        } else {
            Some(module_file(modules)?)
        };
        // Defined in the module's file or folder, or named in its file (a re-export).
        let here = |item: &str| match &region {
            None => self.names.contains_key(item),
            Some((file, folder)) => {
                let defined = self.names.get(item).is_some_and(|files| {
                    files
                        .iter()
                        .any(|f| f == file || folder.as_ref().is_some_and(|d| f.starts_with(d)))
                });
                defined || words(&read(file.to_str().unwrap())).contains(item)
            }
        };
        match items {
            [item] if here(item) => Ok(()),
            [item] => Err(format!(
                "`{item}` is not defined in module {}",
                modules.join("::")
            )),
            [ty, member] if !(self.types.contains(*ty) && here(ty)) => {
                Err(format!("no type `{ty}` there"))
            }
            [ty, member] if self.members.contains_key(&format!("{ty}::{member}")) => Ok(()),
            [ty, member] => Err(format!("`{ty}` has no method, field or variant `{member}`")),
            _ => Err("a path this check cannot follow".into()),
        }
    }

    /// Whether the Rust name `name` (as [`rust_name`] gives it) is defined in `file` (relative to
    /// the crate); the error says where it is defined instead.
    fn defined_in(&self, name: &str, file: &Path) -> Result<(), String> {
        let mut segments: Vec<&str> = name.split("::").collect();
        if matches!(segments[0], "crate" | "tutorial13" | "self") {
            segments.remove(0);
        }
        let modules = segments[..segments.len() - 1]
            .iter()
            .take_while(|s| s.starts_with(|c: char| c.is_ascii_lowercase()))
            .count();
        let (key, defined) = match &segments[modules..] {
            [item] => (item.to_string(), &self.names),
            [ty, member] => (format!("{ty}::{member}"), &self.members),
            _ => return Err("a path this check cannot follow".into()),
        };
        let files = defined.get(&key).map(Vec::as_slice).unwrap_or_default();
        if files.iter().any(|f| f == file) {
            return Ok(());
        }
        let elsewhere = match files {
            [] => "nowhere in the code".to_string(),
            _ => {
                let files: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
                format!("in {}", files.join(", "))
            }
        };
        Err(format!(
            "{} does not define `{key}`; it is defined {elsewhere}",
            file.display()
        ))
    }

    /// `Some(result)` when `span` is a relative path into one of the repository's folders.
    fn repo_path(&self, span: &str) -> Option<Result<(), String>> {
        let plain = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/' | '*');
        if !REPO_DIRS.iter().any(|d| span.starts_with(d)) || !span.chars().all(plain) {
            return None;
        }
        let root = common::manifest();
        let found = match span.strip_suffix('*') {
            Some(prefix) => {
                let (dir, start) = prefix.rsplit_once('/').unwrap_or(("", prefix));
                fs::read_dir(root.join(dir)).is_ok_and(|entries| {
                    entries
                        .flatten()
                        .any(|e| e.file_name().to_string_lossy().starts_with(start))
                })
            }
            None => root.join(span).exists(),
        };
        Some(match found {
            true => Ok(()),
            false => Err("no such file or folder".into()),
        })
    }
}

/// The Rust name a span stands for, if it is taken as one (see the module documentation).
fn rust_name(span: &str) -> Option<String> {
    let mut name = span.to_string();
    // `f(x, y)` → `f`; `get::<T>` → `get`.
    if name.ends_with(')') {
        name.truncate(name.find('(')?);
    }
    if let Some(i) = name.find("::<") {
        let end = i + name[i..].find('>')? + 1;
        name.replace_range(i..end, "");
    }
    let segments: Vec<&str> = name.split("::").collect();
    if !segments.iter().all(|s| is_ident(s)) {
        return None;
    }
    if segments.len() > 1 {
        return (!FOREIGN_PREFIXES.contains(&segments[0])).then_some(name);
    }
    let taken = is_snake(&name) || is_upper_camel(&name) || is_screaming(&name);
    taken.then_some(name)
}

/// The file of module `a::b::c` (`a/b/c.rs` or `a/b/c/mod.rs` under one of [`MODULE_ROOTS`]), and
/// the folder of its submodules, both relative to the crate.
fn module_file(modules: &[&str]) -> Result<(PathBuf, Option<PathBuf>), String> {
    let root = common::manifest();
    'roots: for start in MODULE_ROOTS {
        let mut dir = PathBuf::from(start);
        let mut file = PathBuf::new();
        for module in modules {
            let as_file = dir.join(format!("{module}.rs"));
            let as_folder = dir.join(module).join("mod.rs");
            file = match (
                root.join(&as_file).is_file(),
                root.join(&as_folder).is_file(),
            ) {
                (true, _) => as_file,
                (_, true) => as_folder,
                _ => continue 'roots,
            };
            dir = dir.join(module);
        }
        let folder = root.join(&dir).is_dir().then_some(dir);
        return Ok((file, folder));
    }
    Err(format!("no module file for {}", modules.join("::")))
}

fn words(text: &str) -> HashSet<&str> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
        .collect()
}

/// Identifiers, `::`, `->`, `=>` and single punctuation characters (numbers are dropped).
fn tokens(code: &str) -> Vec<String> {
    let chars: Vec<char> = code.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push(chars[start..i].iter().collect());
            continue;
        }
        if c.is_ascii_digit() {
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            continue;
        }
        let two: String = chars[i..(i + 2).min(chars.len())].iter().collect();
        if matches!(two.as_str(), "::" | "->" | "=>") {
            tokens.push(two);
            i += 2;
            continue;
        }
        if !c.is_whitespace() {
            tokens.push(c.to_string());
        }
        i += 1;
    }
    tokens
}

// Fails if a picture in the README or docs/ is not what the program renders now with the command
// that made it (run from the checkout, as the README's commands run): bit for bit on the reference
// renderer, where they were made; elsewhere it says it is skipped. With TUTORIAL13_UPDATE_DOCS=1 it
// rewrites them instead. (docs/photometric.png has its own test in `photometric::`.)
#[test]
fn the_docs_pictures_are_what_the_program_renders() {
    let pictures: [(&str, &[&str]); 2] = [
        ("docs/first-frame.png", &["--headless"]),
        (
            "docs/panel.png",
            &["--headless", "--debug-lines", "--panel"],
        ),
    ];
    let update = std::env::var_os("TUTORIAL13_UPDATE_DOCS").is_some();
    if !update && !common::reference_renderer_here("the_docs_pictures_are_what_the_program_renders")
    {
        return;
    }
    let root = common::manifest();
    let out = common::scratch("docs-pictures");
    for (picture, args) in pictures {
        let rendered = out.join(Path::new(picture).file_name().unwrap());
        let run = common::run(
            common::tutorial13()
                .args(args)
                .arg("--screenshot")
                .arg(&rendered)
                .current_dir(root),
        );
        assert!(
            run.status.success(),
            "{picture}: {}",
            common::text(&run.stderr)
        );
        let now = image::open(&rendered).unwrap().into_rgb8();
        if update {
            now.save(root.join(picture)).unwrap();
            println!("{picture} rewritten (TUTORIAL13_UPDATE_DOCS)");
            continue;
        }
        let committed = image::open(root.join(picture)).unwrap().into_rgb8();
        let (differing, max, bbox) = common::pixel_diff(&committed, &now);
        assert!(
            differing == 0,
            "{picture}: {differing} pixels differ from `tutorial13 {}` (by up to {max}, within \
             {bbox:?}; it is in {}); rewrite it with TUTORIAL13_UPDATE_DOCS=1 cargo test --release \
             -- docs::",
            args.join(" "),
            rendered.display()
        );
    }
}

// Fails if .ci/run checks another list of the tutorial's files than the tests read
// (`ORIGINAL_FILES`): CI would pass with one missing and the tests would then fail, or check one
// that no test needs.
#[test]
fn ci_checks_the_tutorials_files_the_tests_read() {
    let run = std::fs::read_to_string(common::manifest().join(".ci/run")).unwrap();
    let listed: Vec<&str> = run
        .lines()
        .find_map(|line| line.strip_prefix("for f in cylinder.obj"))
        .map(|rest| {
            std::iter::once("cylinder.obj")
                .chain(rest.trim_end_matches("; do").split_whitespace())
                .collect()
        })
        .expect(".ci/run's loop over the tutorial's files");
    assert_eq!(listed, common::ORIGINAL_FILES);
}
