//! A model's parts by name, for a bake that pairs LOW's parts with HIGH's (`--match-names`): an
//! OBJ's objects and groups (a face belongs to the last `o` or `g` line before it), a glTF's mesh
//! instances (each named by its node, else by its mesh). Faces before any name, and glTF meshes
//! without one, are the unnamed part "".
//!
//! An OBJ's names are read from its text when asked, in a pass of their own: the reader of the
//! soup does not keep them, and every other reader of a model would pay for the pass.

use std::ops::Range;
use std::path::Path;

use super::{Format, Model};
use crate::{Error, Result};

/// A run of triangles under one name, in the file's order (the same name may run again later).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Part {
    pub name: String,
    /// Indices among the file's triangles (faces fanned as written).
    pub triangles: Range<usize>,
}

/// Each of a model's soup triangles' part.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PartNames {
    /// Each name once, in the order the file first gives it.
    pub names: Vec<String>,
    /// An index into `names` for each soup triangle.
    pub of_triangle: Vec<u32>,
}

/// `model`'s parts, its soup's order; `triangles` is its soup's count (a bake moves HIGH's soup
/// out of its model); `read_file` reads an OBJ's text again (from [`Model::path`]).
pub fn part_names(
    model: &Model,
    triangles: usize,
    read_file: impl Fn(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<PartNames> {
    let path = &model.path;
    let runs = match Format::of(path) {
        Some(Format::Gltf) => model.parts.clone(),
        _ => {
            let bytes = read_file(path).map_err(|e| Error::io(path, e))?;
            obj_parts(&String::from_utf8_lossy(&bytes))
        }
    };
    let counted = runs.last().map_or(0, |r| r.triangles.end);
    if counted != triangles {
        // The reader and this pass count faces alike; the fuzz target `model` checks it.
        return Err(Error::Obj {
            path: path.to_path_buf(),
            reason: format!(
                "its names cover {counted} triangles where {triangles} were read (please report it)"
            ),
        });
    }
    let mut names: Vec<String> = Vec::new();
    let mut of_file_triangle = vec![0u32; triangles];
    for run in &runs {
        let index = match names.iter().position(|n| *n == run.name) {
            Some(i) => i,
            None => {
                names.push(run.name.clone());
                names.len() - 1
            }
        };
        of_file_triangle[run.triangles.clone()].fill(index as u32);
    }
    let of_triangle = match model.file_order.is_empty() {
        true => of_file_triangle,
        false => model
            .file_order
            .iter()
            .map(|&f| of_file_triangle[f as usize])
            .collect(),
    };
    Ok(PartNames { names, of_triangle })
}

/// An OBJ's runs of faces under each `o` or `g` name, each face counted as the triangles it fans
/// into (corners − 2), as the reader counts them. Lines split as the reader splits them (at `\n`);
/// a name is the rest of its line, trimmed.
pub fn obj_parts(text: &str) -> Vec<Part> {
    let mut parts: Vec<Part> = Vec::new();
    let mut name = "";
    let mut count = 0;
    for line in text.split('\n') {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("f") => {
                let corners = words.count();
                if corners < 3 {
                    continue; // the reader refuses such a file
                }
                match parts.last_mut() {
                    Some(last) if last.name == name && last.triangles.end == count => {}
                    _ => parts.push(Part {
                        name: name.to_string(),
                        triangles: count..count,
                    }),
                }
                count += corners - 2;
                parts.last_mut().expect("pushed above").triangles.end = count;
            }
            Some(keyword @ ("o" | "g")) => {
                let rest = line.trim_start()[keyword.len()..].trim();
                name = rest;
            }
            _ => {}
        }
    }
    parts
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails if a face is given to the wrong name, a polygon counts other than its fan's
    /// triangles, or a name is not the rest of its line.
    #[test]
    fn faces_belong_to_the_last_object_or_group_line() {
        let text = "v 0 0 0\nf 1 1 1\no barrel_low \nf 1 1 1 1\r\ng grip_low_Material\tB\n\
                    f 1 1 1\nf 1 1 1 1 1\nl 1 1 1\no barrel_low\nf 1 1 1\n";
        let part = |name: &str, triangles: Range<usize>| Part {
            name: name.into(),
            triangles,
        };
        assert_eq!(
            obj_parts(text),
            [
                part("", 0..1),
                part("barrel_low", 1..3),
                part("grip_low_Material\tB", 3..7),
                part("barrel_low", 7..8),
            ]
        );
    }
}
