//! Excerpts of the files the binary is built from, found by what they are: a Rust item by its path
//! (`common::vboindexer::index_vbo_tbn`, `scenes::cylinder::tutorial13::Tutorial13::draw_with`,
//! `scenes::cylinder::tutorial13::impl Tutorial13`) or a region between two marker comments
//! (`// #region name` … `// #endregion name`, in a shader or a Rust file). Nothing is copied into
//! the tour: a renamed item or a removed marker is an error here, which the tour's test turns into
//! a failure (`tests/all/tour.rs`).
//!
//! The resolver reads text, not syntax trees: comments, strings and character literals are blanked
//! out first, so that a brace or a name inside them does not count; an item runs from its doc
//! comments and attributes to the `}` that closes its body, or to the `;` that ends it. Written here
//! rather than taken from a crate (docify's `embed!` does this for Rust items at compile time) to
//! keep the build lean: docify brings syn's full parser and a proc macro into the README's build,
//! and it has no answer for the shaders' regions.

use super::sources;

/// A piece of a source file, as the binary holds it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Excerpt {
    /// The file's path in the repository (`src/common/vboindexer.rs`, `shaders/…`).
    pub file: String,
    /// Its first and last line, counted from 1, both included.
    pub lines: (usize, usize),
    /// Those lines, as written.
    pub text: &'static str,
}

/// Why an excerpt could not be taken (one line, naming what was asked for).
pub type Missing = String;

/// The Rust item at `path` (see the module's documentation), in the embedded sources.
pub fn rust_item(path: &str) -> Result<Excerpt, Missing> {
    let (file, text, item) = rust_file_of(path)?;
    let span = find_item(text, &item).ok_or_else(|| format!("{path}: not found in {file}"))?;
    excerpt(&file, text, span, path)
}

/// The lines between `// #region name` and `// #endregion name` in `file` (a path in the
/// repository: `shaders/…` or `src/…`).
pub fn region(file: &str, name: &str) -> Result<Excerpt, Missing> {
    let text = sources::text(file).ok_or_else(|| format!("{file}: not a file the tour embeds"))?;
    let what = format!("{file}, region {name}");
    let start = marker_line(text, "#region", name)
        .ok_or_else(|| format!("{what}: no `// #region {name}`"))?;
    let end = marker_line(&text[start..], "#endregion", name)
        .map(|end| start + end)
        .ok_or_else(|| format!("{what}: no `// #endregion {name}` after its start"))?;
    // From the line after the start marker to the end of the line before the end marker.
    let first = text[start..]
        .find('\n')
        .map_or(text.len(), |i| start + i + 1);
    let last = text[..end].rfind('\n').map_or(first, |i| i + 1);
    excerpt(file, text, (first, last.max(first)), &what)
}

/// `text[span]` widened to whole lines, with its line numbers; an empty (all-blank) one is missing.
fn excerpt(
    file: &str,
    text: &'static str,
    span: (usize, usize),
    what: &str,
) -> Result<Excerpt, Missing> {
    let (start, end) = span;
    let start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let end = text[end..].find('\n').map_or(text.len(), |i| end + i);
    let body = text[start..end].trim_end_matches('\n');
    if body.trim().is_empty() {
        return Err(format!("{what}: empty in {file}"));
    }
    let first = text[..start].matches('\n').count() + 1;
    Ok(Excerpt {
        file: file.to_string(),
        lines: (first, first + body.matches('\n').count()),
        text: body,
    })
}

/// The byte offset of the line holding `// marker name` (the name a whole word after the marker).
fn marker_line(text: &str, marker: &str, name: &str) -> Option<usize> {
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim();
        if let Some(rest) = trimmed.strip_prefix("//").map(str::trim_start) {
            if let Some(rest) = rest.strip_prefix(marker) {
                if rest.trim() == name {
                    return Some(offset);
                }
            }
        }
        offset += line.len();
    }
    None
}

/// The embedded file of the module an item path names, and the item's own part of the path.
/// `scenes::cylinder::tutorial13::Tutorial13::draw_with`: the module is the run of lower-case
/// segments (`src/scenes/cylinder/tutorial13.rs`, or `…/mod.rs`), the item the rest.
fn rust_file_of(path: &str) -> Result<(String, &'static str, Vec<&str>), Missing> {
    let path = path.strip_prefix("crate::").unwrap_or(path);
    let segments: Vec<&str> = path.split("::").collect();
    // The module path is the longest run of leading segments that names an embedded file.
    for split in (1..segments.len()).rev() {
        let module = segments[..split].join("/");
        for candidate in [format!("src/{module}.rs"), format!("src/{module}/mod.rs")] {
            if let Some(text) = sources::text(&candidate) {
                return Ok((candidate, text, segments[split..].to_vec()));
            }
        }
    }
    Err(format!(
        "{path}: no embedded source file for its module (src/tour/sources.rs lists them)"
    ))
}

/// The byte span of `item` (one name, `Type::member`, or `impl …`) in `text`.
fn find_item(text: &str, item: &[&str]) -> Option<(usize, usize)> {
    let code = code_only(text);
    match item {
        [impl_header] if impl_header.starts_with("impl ") => {
            let (header_start, open) = impl_blocks(&code)
                .into_iter()
                // The header as written: the code has its lifetimes blanked.
                .find(|&(start, open)| normalized(&text[start..open]) == normalized(impl_header))?;
            let close = matching_brace(&code, open)?;
            Some((
                with_doc_and_attributes(text, &code, header_start),
                close + 1,
            ))
        }
        [name] => definition(text, &code, name, 0, code.len()),
        [owner, member] => impl_blocks(&code)
            .into_iter()
            .filter(|&(start, open)| impl_is_for(&code[start..open], owner))
            .find_map(|(_, open)| {
                let close = matching_brace(&code, open)?;
                definition(text, &code, member, open + 1, close)
            }),
        _ => None,
    }
}

/// The span of the first item named `name` defined between `from` and `to` (any nesting: items
/// inside a macro's braces count too).
fn definition(
    text: &str,
    code: &str,
    name: &str,
    from: usize,
    to: usize,
) -> Option<(usize, usize)> {
    const KEYWORDS: [&str; 10] = [
        "fn",
        "struct",
        "enum",
        "trait",
        "type",
        "const",
        "static",
        "mod",
        "union",
        "macro_rules!",
    ];
    let mut at = from;
    while let Some(found) = code[at..to].find(name) {
        let start = at + found;
        at = start + name.len();
        let after = code[at..].chars().next();
        if after.is_some_and(is_ident_char) {
            continue;
        }
        // `fn name`: a keyword, whitespace, then the name (not `something_fn name`).
        let before = code[..start].trim_end();
        if before.len() == start {
            continue;
        }
        let keyword = KEYWORDS.iter().find(|k| {
            before.ends_with(*k) && !before[..before.len() - k.len()].ends_with(is_ident_char)
        });
        let Some(keyword) = keyword else { continue };
        let keyword_start = before.len() - keyword.len();
        let end = item_end(code, at, keyword)?;
        return Some((with_doc_and_attributes(text, code, keyword_start), end));
    }
    None
}

/// Where an item whose name ends at `at` ends: after the `}` closing its body (or the `;` of an
/// item without one), brackets counted so that a `;` or `{` inside a type or a value does not end it.
fn item_end(code: &str, at: usize, keyword: &str) -> Option<usize> {
    let block_item = matches!(
        keyword,
        "fn" | "struct" | "enum" | "trait" | "mod" | "union" | "macro_rules!"
    );
    let mut depth = 0usize;
    for (i, c) in code[at..].char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth = depth.checked_sub(1)?,
            '{' if depth == 0 && block_item => {
                return matching_brace(code, at + i).map(|close| close + 1)
            }
            '{' => depth += 1,
            '}' => depth = depth.checked_sub(1)?,
            ';' if depth == 0 => return Some(at + i + 1),
            _ => {}
        }
    }
    None
}

/// The offset of the `}` matching the `{` at `open`.
fn matching_brace(code: &str, open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (i, c) in code[open..].char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return Some(open + i);
                }
            }
            _ => {}
        }
    }
    None
}

/// Every `impl` block: the offset of its `impl` keyword and of its body's `{`.
fn impl_blocks(code: &str) -> Vec<(usize, usize)> {
    let mut blocks = Vec::new();
    let mut at = 0;
    while let Some(found) = code[at..].find("impl") {
        let start = at + found;
        at = start + 4;
        let word_before = code[..start].ends_with(is_ident_char);
        let word_after = code[at..].starts_with(is_ident_char);
        // An impl block starts a statement (`-> impl Trait {` is a function's return type).
        let previous = code[..start].trim_end();
        let starts_item = previous.is_empty()
            || previous.ends_with(['}', ';', '{', ']'])
            || previous.ends_with("unsafe");
        let header = code[at..]
            .find(['{', ';', ')', ',', '='])
            .map(|i| (i, &code[at + i..at + i + 1]));
        if word_before || word_after || !starts_item {
            continue;
        }
        if let Some((i, "{")) = header {
            blocks.push((start, at + i));
        }
    }
    blocks
}

/// Whether an `impl` header (`impl<T> Trait for path::Owner<T>`) implements something for `owner`.
fn impl_is_for(header: &str, owner: &str) -> bool {
    let target = header
        .rsplit_once(" for ")
        .map_or(header.trim_start_matches("impl"), |(_, t)| t);
    // Generics at the start (`impl<S: 'static> Control<S>`) and at the end are left out.
    let target = target.trim();
    let target = match target.strip_prefix('<') {
        Some(_) => target.split_once('>').map_or(target, |(_, rest)| rest),
        None => target,
    };
    let name = target.trim().split('<').next().unwrap_or("").trim();
    name.rsplit("::").next() == Some(owner)
}

/// Whitespace collapsed to single spaces.
fn normalized(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The start of the line at `start`, moved up over the doc comments and attributes right above it.
fn with_doc_and_attributes(text: &str, code: &str, start: usize) -> usize {
    let mut line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    loop {
        if line_start == 0 {
            return 0;
        }
        let previous = text[..line_start - 1].rfind('\n').map_or(0, |i| i + 1);
        let line = text[previous..line_start - 1].trim();
        let code_line = code[previous..line_start - 1].trim();
        if line.starts_with("///") || line.starts_with("#[") {
            line_start = previous;
        } else if code_line.ends_with(']') && !code_line.starts_with("#[") {
            // The last line of an attribute written over several lines: up to its `#[`.
            match text[..line_start].rfind("#[") {
                Some(open) => line_start = text[..open].rfind('\n').map_or(0, |i| i + 1),
                None => return line_start,
            }
        } else {
            return line_start;
        }
    }
}

/// Rust source `text` with its comments, string literals, character literals and lifetimes turned
/// into spaces (line breaks kept), so that only code is searched and counted: a brace or a name in
/// them is not read as code. Byte offsets stay those of `text`. (tests/all/docs.rs reads the names
/// the code defines through it too.)
pub fn code_only(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = bytes.to_vec();
    let blank = |out: &mut Vec<u8>, from: usize, to: usize| {
        for b in &mut out[from..to] {
            if *b != b'\n' {
                *b = b' ';
            }
        }
    };
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                let end = text[i..].find('\n').map_or(bytes.len(), |e| i + e);
                blank(&mut out, i, end);
                i = end;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                let mut depth = 0;
                let mut j = i;
                while j < bytes.len() {
                    if bytes[j..].starts_with(b"/*") {
                        depth += 1;
                        j += 2;
                    } else if bytes[j..].starts_with(b"*/") {
                        depth -= 1;
                        j += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        j += 1;
                    }
                }
                blank(&mut out, i, j);
                i = j;
            }
            b'r' | b'b' if !ident_before(bytes, i) && raw_string(&bytes[i..]).is_some() => {
                let (prefix, hashes) = raw_string(&bytes[i..]).unwrap_or((1, 0));
                let close: Vec<u8> = std::iter::once(b'"')
                    .chain(std::iter::repeat_n(b'#', hashes))
                    .collect();
                let body = i + prefix + hashes + 1;
                let end = find_bytes(&bytes[body..], &close)
                    .map_or(bytes.len(), |e| body + e + close.len());
                blank(&mut out, i, end);
                i = end;
            }
            b'"' => {
                let mut j = i + 1;
                while j < bytes.len() && bytes[j] != b'"' {
                    j += if bytes[j] == b'\\' { 2 } else { 1 };
                }
                let end = (j + 1).min(bytes.len());
                blank(&mut out, i, end);
                i = end;
            }
            b'\'' => {
                // A character literal ('x', '\n', '{'), or a lifetime or label ('a, 'static).
                let end = if bytes.get(i + 1) == Some(&b'\\') {
                    // The character after the backslash is escaped, whatever it is (`'\''`).
                    let from = (i + 3).min(bytes.len());
                    bytes[from..]
                        .iter()
                        .position(|&b| b == b'\'')
                        .map(|e| from + e + 1)
                } else {
                    let c = text[i + 1..].chars().next();
                    c.and_then(|c| {
                        let after = i + 1 + c.len_utf8();
                        (bytes.get(after) == Some(&b'\'')).then_some(after + 1)
                    })
                };
                let end = end.unwrap_or_else(|| {
                    let name = bytes[i + 1..]
                        .iter()
                        .take_while(|&&b| b.is_ascii_alphanumeric() || b == b'_');
                    i + 1 + name.count()
                });
                blank(&mut out, i, end);
                i = end;
            }
            _ => i += 1,
        }
    }
    // Only ASCII bytes were replaced, by ASCII, and whole characters at that: still UTF-8.
    String::from_utf8(out).unwrap_or_default()
}

/// If a raw string opens here (`r"`, `r#"`, `br"`, …): the length of its `r` or `br` and how many
/// `#` it has.
fn raw_string(bytes: &[u8]) -> Option<(usize, usize)> {
    let prefix = if bytes.starts_with(b"br") { 2 } else { 1 };
    if bytes[prefix - 1] != b'r' {
        return None;
    }
    let hashes = bytes[prefix..].iter().take_while(|&&b| b == b'#').count();
    (bytes.get(prefix + hashes) == Some(&b'"')).then_some((prefix, hashes))
}

/// Whether the byte before `i` continues an identifier (so an `r` there is no raw string's).
fn ident_before(bytes: &[u8], i: usize) -> bool {
    i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_')
}

fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

fn find_bytes(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOURCE: &str = r#"//! A module.

/// Adds.
#[inline]
pub fn add(a: u32, b: u32) -> u32 {
    // A brace in a comment: {
    let s = "a brace in a string: {";
    let c = '{';
    a + b + s.len() as u32 + c as u32
}

pub const LIMIT: [u32; 2] = [1, { 2 }];

struct Thing<'a> {
    name: &'a str,
}

impl<'a> Thing<'a> {
    /// Its name.
    fn name(&self) -> &'a str {
        self.name
    }
}

impl std::fmt::Display for Thing<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.name)
    }
}
"#;

    fn lines(span: (usize, usize)) -> Vec<&'static str> {
        SOURCE[span.0..span.1].lines().collect()
    }

    // Fails if an item's extent is cut at a brace inside a comment, a string or a character
    // literal, leaves out its doc comment and attribute, or runs past its end.
    #[test]
    fn an_item_runs_from_its_doc_to_its_closing_brace() {
        let add = lines(find_item(SOURCE, &["add"]).unwrap());
        assert_eq!(add.first(), Some(&"/// Adds."));
        assert_eq!(add.last(), Some(&"}"));
        assert_eq!(add.len(), 8);
        let limit = lines(find_item(SOURCE, &["LIMIT"]).unwrap());
        assert_eq!(limit, ["pub const LIMIT: [u32; 2] = [1, { 2 }];"]);
    }

    // Fails if a raw string, a byte raw string, an escaped quote or a lifetime leaves a brace, a quote
    // or a name in the code, or if a byte moves (the spans are taken from the text by the code's
    // offsets).
    #[test]
    fn code_only_blanks_all_but_code() {
        let text = "let a = r#\"{\"#; let b = br\"}\"; let c = '\\''; fn f<'a>(x: &'a str) {}\n";
        let code = code_only(text);
        assert_eq!(code.len(), text.len());
        assert_eq!(code.matches(['{', '}']).count(), 2);
        assert!(!code.contains(['\'', '"']), "{code}");
        assert!(code.ends_with("fn f<  >(x: &   str) {}\n"), "{code}");
    }

    // Fails if a method is looked for outside its type's impl blocks, if a trait impl is not
    // found by its header, or if a lifetime is taken for a character literal (which would blank
    // the rest of the file and find nothing).
    #[test]
    fn methods_and_impls_are_found_by_their_type() {
        let name = lines(find_item(SOURCE, &["Thing", "name"]).unwrap());
        assert_eq!(name.first().map(|l| l.trim()), Some("/// Its name."));
        assert_eq!(name.len(), 4);
        let fmt = lines(find_item(SOURCE, &["Thing", "fmt"]).unwrap());
        assert_eq!(fmt.len(), 3);
        let display = lines(find_item(SOURCE, &["impl std::fmt::Display for Thing<'_>"]).unwrap());
        assert_eq!(display.len(), 5);
        assert_eq!(find_item(SOURCE, &["Thing", "missing"]), None);
        assert_eq!(find_item(SOURCE, &["ad"]), None);
    }
}
