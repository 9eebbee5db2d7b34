//! The program's OBJ parse: the file's lines split over the cores, for a learner's model of a
//! million triangles, with the soup of the tutorial's reader ([`crate::common::objloader`]) to the bit.
//!
//! tobj reads one line at a time on one core (a `String` per line, a `Vec` per face, three hash
//! maps per corner): 0.75 s of a 1M-triangle file's 1.7 s to its first frame. This reader reads the
//! statements the tutorial's pipeline uses (`v`, `vt`, `vn`, `f`, `mtllib`, `usemtl`; every other
//! line is skipped, as tobj skips or only names them) straight into the triangle soup, each core a
//! run of whole lines. Numbers are read by the same `str::parse` calls as tobj's and the face
//! check's, so the floats are the same to the bit.
//!
//! It reads only what it is sure tobj and `objloader`'s checks would read the same way. Anything
//! else (a malformed line, an index out of range, a used number that is not finite, no faces) it
//! refuses, and [`read_obj_threaded`] hands the file to the tutorial's reader, whose error is the one the
//! user sees: one set of error messages, however the file was read.

use crate::clock::Instant;
use std::collections::HashMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use glam::{Vec2, Vec3};

use crate::common::objloader::{
    no_materials, obj_error, read_obj as read_obj_with_tobj, utf8, ObjMode, ObjRead, TriangleSoup,
};
use crate::pipeline::on_threads;
use crate::{Error, Result};

/// Reads `path` as the tutorial's `loadOBJ` does ([`crate::common::objloader::load_obj`]), on
/// every core. Errors name the file and the reason.
pub fn load_obj_threaded(path: &Path) -> Result<TriangleSoup> {
    let bytes = crate::files::read(path).map_err(|e| Error::io(path, e))?;
    load_obj_bytes_threaded(&bytes, path)
}

/// [`load_obj_threaded`] on bytes already in memory; `path` is only used in error messages.
pub fn load_obj_bytes_threaded(bytes: &[u8], path: &Path) -> Result<TriangleSoup> {
    Ok(read_obj_threaded(bytes, path, ObjMode::Tutorial, no_materials, None)?.soup)
}

/// [`crate::common::objloader::read_obj`] on every core: the same result, or the same error. The
/// text is cut into `pieces` runs of lines (`None`: one per core, fewer for a small file); the
/// differential tests cut small files too.
pub fn read_obj_threaded(
    bytes: &[u8],
    path: &Path,
    mode: ObjMode,
    materials: impl Fn(&Path) -> tobj::MTLLoadResult,
    pieces: Option<usize>,
) -> Result<ObjRead> {
    let text = utf8(bytes, path)?;
    match read(text, path, mode, &materials, pieces) {
        Outcome::Read(read) => Ok(read),
        Outcome::LoaderPanicked => Err(obj_error(path, "tobj's parser panicked".into())),
        Outcome::ReadIfTobjAgrees(mut read) => {
            let reference = read_obj_with_tobj(bytes, path, mode, materials)?;
            read.materials = reference.materials;
            read.triangle_materials = reference.triangle_materials;
            Ok(read)
        }
        Outcome::Refused => match read_obj_with_tobj(bytes, path, mode, materials) {
            Err(e) => Err(e),
            // Never seen: the fuzz harness's `obj-tobj` target looks for such files.
            Ok(_) => Err(obj_error(
                path,
                "the project's OBJ reader refuses a file tobj reads (please report it)".into(),
            )),
        },
    }
}

/// Files are cut into runs of lines of at least this size: below it a thread costs more than it
/// saves.
const MIN_PIECE: usize = 1 << 20;
/// The index of an element a corner leaves out (a model's normal, computed; a shape's UV, read as
/// (0, 0)).
const LEFT_OUT: u32 = u32::MAX;

/// A face corner's 0-based position, UV and normal indices into the whole file's elements.
type Corner = [u32; 3];

/// What [`read`] made of a file.
enum Outcome {
    /// Read as tobj and the checks read it.
    Read(ObjRead),
    /// Read, but only some `v` lines carry a vertex colour: tobj refuses a face whose position
    /// index is past the colours kept so far, counted where each object or material run ends,
    /// which this reader does not follow. The caller asks tobj, and keeps this soup with tobj's
    /// materials if tobj reads the file too.
    ReadIfTobjAgrees(ObjRead),
    /// Malformed, or not what this reader knows: tobj and the checks decide, and name the error.
    Refused,
    /// A `.mtl` loader panicked (the message tobj's parse gives for it).
    LoaderPanicked,
}

/// One `mtllib` or `usemtl` statement, with the name as tobj takes it from the line.
enum Statement<'a> {
    Mtllib(&'a str),
    Usemtl(&'a str),
}

/// Why a piece stopped before its end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stop {
    /// Something [`read`] refuses.
    Refused,
    /// A relative index in a piece whose preceding elements are not counted yet.
    RelativeIndex,
}

/// What one run of lines declares and uses.
#[derive(Default)]
struct Piece<'a> {
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
    /// Every face fanned into triangles from its first corner, as tobj triangulates.
    triangles: Vec<[Corner; 3]>,
    /// Per kind (position, UV, normal), the largest `index − elements this piece declared before
    /// it` of a positive index: the piece is in range if that is at most the elements declared
    /// before the piece.
    reach: [i64; 3],
    /// With the number of triangles before each.
    statements: Vec<(usize, Statement<'a>)>,
    /// Per kind (position, UV, normal), the corners that give its index and those that leave it out.
    corners_with: [usize; 3],
    corners_without: [usize; 3],
    /// Vertex colour values tobj keeps (`v x y z r g b`; it stops at the first that is not a
    /// number).
    colours: usize,
    stop: Option<Stop>,
}

/// Reads `text` as the tutorial's reader does with tobj and the face check. `materials` loads an
/// `mtllib`. `pieces`: how many runs of lines to cut the text into (by default one per core, fewer
/// for a small file; the differential tests cut small files too).
fn read(
    text: &str,
    path: &Path,
    mode: ObjMode,
    materials: &dyn Fn(&Path) -> tobj::MTLLoadResult,
    pieces: Option<usize>,
) -> Outcome {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let count = pieces.unwrap_or(cores.min(text.len() / MIN_PIECE));
    let texts = cut(text, count.max(1));
    let start = Instant::now();
    // The first piece starts at the file's start: its relative indices resolve as they are read.
    // The others stop at their first one and are read again below, once the elements before them
    // are counted (rare: exporters write absolute indices).
    let mut pieces = on_threads(texts.iter().enumerate().collect(), |(k, text)| {
        parse_piece(text, mode, (k == 0).then_some([0; 3]))
    });
    let mut before = [0usize; 3];
    for (piece, text) in pieces.iter_mut().zip(&texts) {
        if piece.stop == Some(Stop::RelativeIndex) {
            *piece = parse_piece(text, mode, Some(before));
        }
        let out_of_range = (0..3).any(|k| piece.reach[k] > before[k] as i64);
        if piece.stop.is_some() || out_of_range {
            return Outcome::Refused;
        }
        before[0] += piece.positions.len();
        before[1] += piece.uvs.len();
        before[2] += piece.normals.len();
    }
    let [_, with_uv, with_normal] =
        [0, 1, 2].map(|k| pieces.iter().map(|p| p.corners_with[k]).sum());
    let [_, without_uv, without_normal]: [usize; 3] =
        [0, 1, 2].map(|k| pieces.iter().map(|p| p.corners_without[k]).sum());
    let triangles: usize = pieces.iter().map(|p| p.triangles.len()).sum();
    let mixed = |with: usize, without: usize| with > 0 && without > 0;
    if mixed(with_normal, without_normal) || mixed(with_uv, without_uv) || triangles == 0 {
        return Outcome::Refused;
    }
    let normals_missing = mode != ObjMode::Tutorial && with_normal == 0;
    let uvs_missing = without_uv > 0;

    let parsed = start.elapsed();
    let Some((soup, position_indices)) = deindex(&pieces, mode, normals_missing) else {
        return Outcome::Refused; // a used number that is not finite
    };
    log::debug!(
        "{}: parsed in {} piece(s) in {:.1} ms, triangle soup written in {:.1} ms",
        path.display(),
        texts.len(),
        parsed.as_secs_f64() * 1e3,
        (start.elapsed() - parsed).as_secs_f64() * 1e3
    );
    let mut read = ObjRead {
        soup,
        position_indices,
        normals_missing,
        uvs_missing,
        ..Default::default()
    };
    let colours: usize = pieces.iter().map(|p| p.colours).sum();
    if colours != 0 && colours != 3 * before[0] {
        return Outcome::ReadIfTobjAgrees(read);
    }
    match materials_of(&pieces, triangles, materials) {
        Some((loaded, triangle_materials)) => {
            read.materials = loaded;
            read.triangle_materials = triangle_materials;
            Outcome::Read(read)
        }
        None => Outcome::LoaderPanicked,
    }
}

/// `text` cut after line breaks into `count` pieces of about the same size (the last ones empty if
/// it has fewer lines).
fn cut(text: &str, count: usize) -> Vec<&str> {
    let mut pieces = Vec::with_capacity(count);
    let mut rest = text;
    for left in (1..count).rev() {
        let target = rest.len() / (left + 1);
        let cut = match rest.as_bytes()[target..].iter().position(|&b| b == b'\n') {
            Some(i) => target + i + 1,
            None => rest.len(),
        };
        let (piece, tail) = rest.split_at(cut);
        pieces.push(piece);
        rest = tail;
    }
    pieces.push(rest);
    pieces
}

/// Reads one piece. `before` is the count of each kind of element before it, if known.
fn parse_piece(text: &str, mode: ObjMode, before: Option<[usize; 3]>) -> Piece<'_> {
    let mut piece = Piece {
        reach: [i64::MIN; 3],
        ..Default::default()
    };
    let mut face = Vec::new();
    // Lines as tobj and the face check split them: at `\n`; a `\r` before it is whitespace.
    for line in text.split('\n') {
        // Words as `split_whitespace` splits them; on ASCII text without its Unicode tables.
        let read = match line.is_ascii() {
            true => piece.line(line, AsciiWords { line, at: 0 }, mode, before, &mut face),
            false => piece.line(line, line.split_whitespace(), mode, before, &mut face),
        };
        if let Err(stop) = read {
            piece.stop = Some(stop);
            break;
        }
    }
    piece
}

/// The words of an ASCII line, split where `char::is_whitespace` splits them.
struct AsciiWords<'a> {
    line: &'a str,
    at: usize,
}

impl<'a> Iterator for AsciiWords<'a> {
    type Item = &'a str;

    fn next(&mut self) -> Option<&'a str> {
        let bytes = self.line.as_bytes();
        let start = self.at + bytes[self.at..].iter().position(|&b| !is_space(b))?;
        let end = bytes[start..]
            .iter()
            .position(|&b| is_space(b))
            .map_or(bytes.len(), |n| start + n);
        self.at = end;
        Some(&self.line[start..end])
    }
}

/// `char::is_whitespace` on an ASCII byte (which, unlike `u8::is_ascii_whitespace`, includes the
/// vertical tab).
fn is_space(b: u8) -> bool {
    matches!(b, b'\t' | b'\n' | 0x0B | 0x0C | b'\r' | b' ')
}

impl<'a> Piece<'a> {
    /// One line, as tobj's `parse_obj_line` and the face check read it.
    fn line(
        &mut self,
        line: &'a str,
        mut words: impl Iterator<Item = &'a str>,
        mode: ObjMode,
        before: Option<[usize; 3]>,
        face: &mut Vec<Corner>,
    ) -> Result<(), Stop> {
        // Matched as bytes: a string match calls memcmp for every line.
        match words.next().map(str::as_bytes) {
            Some(b"v") => {
                let [x, y, z] = floats(&mut words).ok_or(Stop::Refused)?;
                let mut position = Vec3::new(x, y, z);
                // Then nothing, a w that divides x, y and z, or a colour.
                match (words.next(), words.next(), words.next(), words.next()) {
                    (None, ..) => {}
                    (Some(w), None, ..) => {
                        let w: f32 = w.parse().map_err(|_| Stop::Refused)?;
                        if w == 0.0 {
                            return Err(Stop::Refused);
                        }
                        position = Vec3::new(x / w, y / w, z / w);
                    }
                    (Some(r), Some(g), Some(b), None) => {
                        let colour = [r, g, b];
                        let kept = colour.iter().take_while(|c| c.parse::<f32>().is_ok());
                        self.colours += kept.count();
                    }
                    _ => return Err(Stop::Refused),
                }
                self.positions.push(position);
            }
            // Further numbers (a w) are not read, as tobj does not read them.
            Some(b"vt") => {
                let [u, v] = floats(&mut words).ok_or(Stop::Refused)?;
                self.uvs.push(Vec2::new(u, v));
            }
            Some(b"vn") => {
                let [x, y, z] = floats(&mut words).ok_or(Stop::Refused)?;
                self.normals.push(Vec3::new(x, y, z));
            }
            Some(b"f") => {
                face.clear();
                for word in words {
                    face.push(self.corner(word, mode, before)?);
                }
                if face.len() < 3 {
                    return Err(Stop::Refused);
                }
                for k in 1..face.len() - 1 {
                    self.triangles.push([face[0], face[k], face[k + 1]]);
                }
            }
            // The name is the rest of the line after its first space, as tobj takes it (a tab
            // after `usemtl` leaves it empty: tobj refuses that).
            Some(b"usemtl") => {
                let name = line.split_once(' ').unwrap_or_default().1.trim();
                if name.is_empty() {
                    return Err(Stop::Refused);
                }
                let statement = Statement::Usemtl(name);
                self.statements.push((self.triangles.len(), statement));
            }
            Some(b"mtllib") => {
                let name = line.split_once(' ').unwrap_or_default().1.trim();
                let statement = Statement::Mtllib(name);
                self.statements.push((self.triangles.len(), statement));
            }
            // Comments, objects, groups, smoothing, points and polylines (dropped: the tutorial's
            // loader skips lines it does not know) change nothing in the soup.
            _ => {}
        }
        Ok(())
    }

    /// One face corner: `v/vt/vn`, in a model also `v/vt` or `v/vt/`, in a shape also `v`, `v/`,
    /// `v//` or `v//vn` (no UV).
    fn corner(
        &mut self,
        word: &str,
        mode: ObjMode,
        before: Option<[usize; 3]>,
    ) -> Result<Corner, Stop> {
        let mut parts = word.as_bytes().split(|&b| b == b'/');
        let (v, vt, vn) = (parts.next(), parts.next(), parts.next());
        let (Some(v), None) = (v, parts.next()) else {
            return Err(Stop::Refused);
        };
        let vt = match vt {
            Some(vt) if !vt.is_empty() => Some(vt),
            _ if mode == ObjMode::Shape => None,
            _ => return Err(Stop::Refused),
        };
        let vn = match vn {
            Some(vn) if !vn.is_empty() => Some(vn),
            _ if mode != ObjMode::Tutorial => None,
            _ => return Err(Stop::Refused),
        };
        let v = self.index(v, 0, before)?;
        let vt = self.index_or_left_out(vt, 1, before)?;
        let vn = self.index_or_left_out(vn, 2, before)?;
        Ok([v, vt, vn])
    }

    /// [`Piece::index`] where the corner gives one, else [`LEFT_OUT`]; counted either way.
    fn index_or_left_out(
        &mut self,
        text: Option<&[u8]>,
        kind: usize,
        before: Option<[usize; 3]>,
    ) -> Result<u32, Stop> {
        match text {
            Some(text) => {
                self.corners_with[kind] += 1;
                self.index(text, kind, before)
            }
            None => {
                self.corners_without[kind] += 1;
                Ok(LEFT_OUT)
            }
        }
    }

    /// One index of kind `kind` (position, UV, normal), 0-based in the whole file.
    fn index(&mut self, text: &[u8], kind: usize, before: Option<[usize; 3]>) -> Result<u32, Stop> {
        let index = parse_index(text).ok_or(Stop::Refused)?;
        let declared = [self.positions.len(), self.uvs.len(), self.normals.len()][kind] as i64;
        let resolved = if index > 0 {
            self.reach[kind] = self.reach[kind].max(index - declared);
            index - 1
        } else if index < 0 {
            // Counts back from the last element declared so far.
            let before = before.ok_or(Stop::RelativeIndex)?;
            before[kind] as i64 + declared + index
        } else {
            return Err(Stop::Refused);
        };
        u32::try_from(resolved).map_err(|_| Stop::Refused)
    }
}

/// An index as the face check reads it (`str::parse::<i64>`; an empty one is `None`): the usual
/// `-?[0-9]+` without its checks, anything else through `parse`.
fn parse_index(text: &[u8]) -> Option<i64> {
    let (negative, digits) = match text {
        [b'-', digits @ ..] => (true, digits),
        digits => (false, digits),
    };
    let by_parse = || std::str::from_utf8(text).ok()?.parse().ok();
    // 18 digits cannot overflow an i64.
    if digits.is_empty() || digits.len() > 18 {
        return by_parse();
    }
    let mut value = 0i64;
    for &d in digits {
        let digit = d.wrapping_sub(b'0');
        if digit > 9 {
            return by_parse();
        }
        value = 10 * value + i64::from(digit);
    }
    Some(if negative { -value } else { value })
}

/// The next `N` words as floats, read as tobj reads them.
fn floats<'a, const N: usize>(words: &mut impl Iterator<Item = &'a str>) -> Option<[f32; N]> {
    let mut values = [0.0; N];
    for value in &mut values {
        *value = words.next()?.parse().ok()?;
    }
    Some(values)
}

/// The triangle soup of every piece's faces, and for a model without normals each corner's position
/// index; `None` if a used number is not finite. Written in as many equal runs of corners as there
/// are pieces, each on a thread of its own: by the pieces themselves, the first (the vertices, the
/// start of a file) had few faces and the last most of them.
fn deindex(
    pieces: &[Piece],
    mode: ObjMode,
    normals_missing: bool,
) -> Option<(TriangleSoup, Vec<u32>)> {
    let positions: Vec<Vec3> = pieces.iter().flat_map(|p| &p.positions).copied().collect();
    let uvs: Vec<Vec2> = pieces.iter().flat_map(|p| &p.uvs).copied().collect();
    let normals: Vec<Vec3> = pieces.iter().flat_map(|p| &p.normals).copied().collect();

    let faces: Vec<&[Corner]> = pieces.iter().map(|p| p.triangles.as_flattened()).collect();
    let corners: usize = faces.iter().map(|f| f.len()).sum();
    let run = corners.div_ceil(pieces.len().max(1)).max(1);
    let sizes: Vec<usize> = (0..corners)
        .step_by(run)
        .map(|start| run.min(corners - start))
        .collect();
    // Zeroed by the system, untouched: each thread below faults in its own part.
    let mut soup = TriangleSoup {
        vertices: bytemuck::zeroed_vec(corners),
        uvs: bytemuck::zeroed_vec(corners),
        normals: bytemuck::zeroed_vec(if normals_missing { 0 } else { corners }),
    };
    let mut position_indices = vec![0; if normals_missing { corners } else { 0 }];
    let jobs: Vec<_> = (0..sizes.len())
        .zip(split(&mut soup.vertices, &sizes))
        .zip(split(&mut soup.uvs, &sizes))
        .zip(split(&mut soup.normals, &sizes))
        .zip(split(&mut position_indices, &sizes))
        .collect();
    let finite = on_threads(jobs, |((((job, out_p), out_uv), out_n), out_i)| {
        let mut finite = true;
        let start = job * run;
        for (k, &[v, vt, vn]) in corners_in(&faces, start..start + out_p.len()).enumerate() {
            let position = positions[v as usize];
            // A shape without UVs: (0, 0), as a `vt 0 0` every corner named would read.
            let uv = match vt {
                LEFT_OUT => Vec2::ZERO,
                vt => uvs[vt as usize],
            };
            out_p[k] = position;
            // Invert V in the tutorial's mode: its DDS textures are stored upside down.
            out_uv[k] = match mode {
                ObjMode::Tutorial => Vec2::new(uv.x, -uv.y),
                ObjMode::Model | ObjMode::Shape => uv,
            };
            finite &= position.is_finite() && uv.is_finite();
            if normals_missing {
                out_i[k] = v; // the key of the smooth normal the caller computes
            } else {
                out_n[k] = normals[vn as usize];
                finite &= out_n[k].is_finite();
            }
        }
        finite
    });
    finite
        .into_iter()
        .all(|f| f)
        .then_some((soup, position_indices))
}

/// The corners numbered `range` of the pieces' `faces` taken one after the other.
fn corners_in<'f>(
    faces: &'f [&'f [Corner]],
    range: std::ops::Range<usize>,
) -> impl Iterator<Item = &'f Corner> {
    let mut first = 0;
    faces.iter().flat_map(move |face| {
        let (start, end) = (first, first + face.len());
        first = end;
        let (from, to) = (range.start.clamp(start, end), range.end.clamp(start, end));
        &face[from - start..to - start]
    })
}

/// `slice` cut into consecutive parts of `sizes`, or into empty parts if it is empty.
fn split<'s, T>(mut slice: &'s mut [T], sizes: &[usize]) -> Vec<&'s mut [T]> {
    let mut parts = Vec::with_capacity(sizes.len());
    for &size in sizes {
        let size = size.min(slice.len());
        let (part, rest) = std::mem::take(&mut slice).split_at_mut(size);
        parts.push(part);
        slice = rest;
    }
    parts
}

/// The `.mtl` files' materials, loaded in file order as tobj loads them, and each triangle's
/// material (the last `usemtl` before it, by a name loaded before that). `None` if a loader panicked.
#[allow(clippy::type_complexity)]
fn materials_of(
    pieces: &[Piece],
    triangles: usize,
    materials: &dyn Fn(&Path) -> tobj::MTLLoadResult,
) -> Option<(Vec<tobj::Material>, Vec<Option<usize>>)> {
    let mut loaded = Vec::new();
    let mut by_name = HashMap::new();
    let mut current = None;
    let mut triangle_materials = Vec::with_capacity(triangles);
    let mut offset = 0;
    for piece in pieces {
        for (before, statement) in &piece.statements {
            triangle_materials.resize(offset + before, current);
            match *statement {
                Statement::Mtllib(name) => {
                    let result = catch_unwind(AssertUnwindSafe(|| materials(Path::new(name))));
                    // A file that fails to load adds nothing (its names stay unknown).
                    if let Ok((more, names)) = result.ok()? {
                        let first = loaded.len();
                        loaded.extend(more);
                        by_name.extend(names.into_iter().map(|(name, i)| (name, first + i)));
                    }
                }
                Statement::Usemtl(name) => current = by_name.get(name).copied(),
            }
        }
        offset += piece.triangles.len();
    }
    triangle_materials.resize(triangles, current);
    Some((loaded, triangle_materials))
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a cut is not after a line break, loses or repeats text, or the pieces are not of
    // about the same size.
    #[test]
    fn cuts_are_whole_lines() {
        let line = "vt 0.123456 0.654321\n";
        let text = line.repeat(1000);
        for count in [1, 2, 3, 7] {
            let pieces = cut(&text, count);
            assert_eq!(pieces.len(), count);
            assert_eq!(pieces.concat(), text);
            for piece in &pieces {
                assert!(piece.ends_with('\n'), "{piece:?}");
                assert!(piece.len().abs_diff(text.len() / count) <= 2 * line.len());
            }
        }
        assert_eq!(cut("v 0 0 0", 3), ["v 0 0 0", "", ""]);
    }

    // Fails if the ASCII word splitter splits where `split_whitespace` does not.
    #[test]
    fn ascii_words_split_as_split_whitespace() {
        for b in 0..128u8 {
            assert_eq!(is_space(b), char::from(b).is_whitespace(), "byte {b}");
        }
        let line = " v\t1\x0b2\x0c3\r  ";
        let words: Vec<&str> = AsciiWords { line, at: 0 }.collect();
        assert_eq!(words, line.split_whitespace().collect::<Vec<_>>());
    }

    // Fails if an index other than `-?[0-9]{1,18}` is not read as `str::parse::<i64>` reads it.
    #[test]
    fn indices_read_as_parse_reads_them() {
        for text in [
            "1",
            "-1",
            "0",
            "-0",
            "+7",
            "007",
            "",
            "-",
            "1a",
            "999999999999999999",
            "9223372036854775807",
            "9223372036854775808",
            "-9223372036854775808",
            "1 ",
            "١",
        ] {
            assert_eq!(parse_index(text.as_bytes()), text.parse().ok(), "{text:?}");
        }
    }
}
