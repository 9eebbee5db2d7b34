//! Randomness and mutation: the seeded mutator every target's inputs go through.

use super::{Target, MAX_INPUT};

/// SplitMix64: tiny, seedable, good enough to pick mutations.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (n > 0; the tiny modulo bias does not matter here).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    pub fn chance(&mut self, one_in: usize) -> bool {
        self.below(one_in) == 0
    }

    pub(super) fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Numbers that have broken parsers and float code before: index extremes, non-finite and
/// near-overflow floats, the 0.01 tolerance.
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "-1",
    "2",
    "-2",
    "3",
    "-3",
    "7",
    "-9223372036854775808",
    "9223372036854775807",
    "-9223372036854775807",
    "-9223372036854775809",
    "18446744073709551616",
    "4294967296",
    "4294967297",
    "-4294967296",
    "2147483648",
    "65536",
    "65535",
    "nan",
    "NaN",
    "-nan",
    "inf",
    "-inf",
    "infinity",
    "1e38",
    "-1e38",
    "3.4e38",
    "3.4028235e38",
    "-3.4028235e38",
    "1.7e38",
    "-1.7e38",
    "1e39",
    "1e30",
    "1e20",
    "1e-45",
    "1e-38",
    "-0",
    "0.01",
    "0.0099",
    "0.0101",
    "0.005",
    "1e-30",
    "0x10",
    "+1",
    "1.",
    ".5",
];

/// Whole lines worth inserting into OBJ text.
const LINES: &[&str] = &[
    "l 1 2 3",
    "l 1/-3/1 1/1/1 1/1/1",
    "l 1 2",
    "l",
    "p 1",
    "p 1 2 3",
    "f 1/1/1 1/1/1 1/1/1",
    "f -1/-1/-1 -2/-2/-1 -3/-3/-1",
    "f 1//1 2//1 3//1",
    "f 1/1/1 2/2/1",
    "f 1/1/1 2/2/1 3/3/1 4/4/1 5/5/1",
    "f 1/1 2/2 3/3",
    "f",
    "v 1e38 1e38 1e38",
    "v 3.4e38 -3.4e38 0",
    "v -3.4e38 3.4e38 3.4e38",
    "v 0 0 0",
    "v 1 2 3 0",
    "v 1 2 3 1e-40",
    "v 1 2 3 0.5 0.5 0.5",
    "v 1 2",
    "vt 0 0",
    "vt 0.005 0",
    "vt 1e-30 0",
    "vt 0 0 0",
    "vn 0 0 1",
    "vn 0 0 0",
    "vn 1e38 1e38 1e38",
    "o x",
    "o",
    "g group",
    "g",
    "s off",
    "s 1",
    "usemtl m",
    "mtllib m.mtl",
    "# comment",
    "\\",
    "",
];

/// Offsets of header fields: DDS (size, flags, height, width, pitch, depth, mipmap count, pixel
/// format size/flags/FourCC/bits, caps, the DX10 header) and BMP (file size, data offset, DIB size,
/// width, height, planes, bits per pixel, compression, image size).
const DDS_FIELDS: &[usize] = &[4, 8, 12, 16, 20, 24, 28, 76, 80, 84, 88, 108, 112, 128, 132];
const BMP_FIELDS: &[usize] = &[2, 10, 14, 18, 22, 26, 28, 30, 34];
const U32S: &[u32] = &[
    0,
    1,
    2,
    3,
    4,
    5,
    8,
    15,
    16,
    17,
    31,
    32,
    124,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0xFFFF_FFFE,
    0xFFFF,
    0x1_0000,
    16384,
    16385,
    24,
    40,
    54,
    0x3154_5844,
    0x3354_5844,
    0x3554_5844,
    0x3031_5844,
];

/// One random input derived from `base` (and maybe a second pool entry for splices).
pub fn mutate(target: Target, rng: &mut Rng, base: &[u8], pool: &[Vec<u8>]) -> Vec<u8> {
    let mut data = base.to_vec();
    let rounds = 1 + rng.below(4);
    for _ in 0..rounds {
        let text_op = target.is_text() && rng.below(3) != 0;
        if text_op {
            mutate_text(rng, &mut data);
        } else if !target.is_text() && rng.chance(2) {
            mutate_header(target, rng, &mut data);
        } else {
            mutate_bytes(rng, &mut data, pool);
        }
    }
    data.truncate(MAX_INPUT);
    data
}

fn mutate_bytes(rng: &mut Rng, data: &mut Vec<u8>, pool: &[Vec<u8>]) {
    let len = data.len();
    match rng.below(8) {
        0 if len > 0 => {
            let i = rng.below(len);
            data[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            data[i] = *rng.pick(&[0u8, 0xFF, 0x7F, 0x80, 1, b'\n', b'/', b'-', b' ', b'9']);
        }
        2 if len > 0 => {
            // Delete a range.
            let start = rng.below(len);
            let end = (start + 1 + rng.below(64)).min(len);
            data.drain(start..end);
        }
        3 if len > 0 => {
            // Copy a range elsewhere.
            let start = rng.below(len);
            let end = (start + 1 + rng.below(256)).min(len);
            let piece = data[start..end].to_vec();
            let at = rng.below(len + 1);
            data.splice(at..at, piece);
        }
        4 => {
            let at = rng.below(len + 1);
            let count = 1 + rng.below(16);
            let bytes: Vec<u8> = (0..count).map(|_| rng.next_u64() as u8).collect();
            data.splice(at..at, bytes);
        }
        5 if len > 0 => data.truncate(rng.below(len)),
        6 if !pool.is_empty() => {
            // Splice: a prefix of this input, a suffix of another.
            let other = rng.pick(pool);
            let cut = rng.below(len + 1);
            let from = rng.below(other.len() + 1);
            data.truncate(cut);
            data.extend_from_slice(&other[from..]);
        }
        _ if len > 0 => {
            let i = rng.below(len);
            data[i] = data[i].wrapping_add(rng.below(5) as u8).wrapping_sub(2);
        }
        _ => data.extend_from_slice(b"v 0 0 0\n"),
    }
}

fn mutate_header(target: Target, rng: &mut Rng, data: &mut Vec<u8>) {
    let fields = if target == Target::Dds {
        DDS_FIELDS
    } else {
        BMP_FIELDS
    };
    let at = *rng.pick(fields);
    let value = if rng.chance(4) {
        rng.next_u64() as u32 >> rng.below(32)
    } else {
        *rng.pick(U32S)
    };
    if data.len() < at + 4 {
        data.resize(at + 4, 0);
    }
    if rng.chance(3) {
        // Negative sizes (BMP top-down), small signed values.
        let v = -(rng.below(70000) as i32);
        data[at..at + 4].copy_from_slice(&v.to_le_bytes());
    } else {
        data[at..at + 4].copy_from_slice(&value.to_le_bytes());
    }
}

/// Number tokens of `text`: byte ranges of runs of digits, signs, dots, exponents, letters of
/// nan/inf.
fn number_spans(text: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < text.len() {
        if text[i].is_ascii_digit() || text[i] == b'-' || text[i] == b'.' {
            let start = i;
            while i < text.len()
                && (text[i].is_ascii_alphanumeric() || matches!(text[i], b'-' | b'+' | b'.'))
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

fn line_starts(text: &[u8]) -> Vec<usize> {
    let mut starts = vec![0];
    starts.extend(
        text.iter()
            .enumerate()
            .filter(|&(_, &b)| b == b'\n')
            .map(|(i, _)| i + 1),
    );
    starts
}

fn mutate_text(rng: &mut Rng, data: &mut Vec<u8>) {
    match rng.below(7) {
        0 | 1 => {
            // Replace a number with an interesting one.
            let spans = number_spans(data);
            if spans.is_empty() {
                return;
            }
            let (start, end) = *rng.pick(&spans);
            let number = if rng.chance(4) {
                format!("{}", rng.next_u64() as i64 >> rng.below(64))
            } else {
                rng.pick(NUMBERS).to_string()
            };
            data.splice(start..end, number.into_bytes());
        }
        2 => {
            // Insert a line.
            let starts = line_starts(data);
            let at = *rng.pick(&starts);
            let line = if rng.chance(2) {
                random_face(rng)
            } else {
                rng.pick(LINES).to_string()
            };
            data.splice(at..at, format!("{line}\n").into_bytes());
        }
        3 => {
            // Repeat a line (grows the mesh, makes duplicates for the indexer).
            let starts = line_starts(data);
            let i = rng.below(starts.len());
            let end = starts.get(i + 1).copied().unwrap_or(data.len());
            let line = data[starts[i]..end].to_vec();
            let most = if rng.chance(8) { 500 } else { 8 };
            let times = 1 + rng.below(most);
            let mut piece = Vec::new();
            for _ in 0..times {
                piece.extend_from_slice(&line);
                if !line.ends_with(b"\n") {
                    piece.push(b'\n');
                }
            }
            data.splice(end..end, piece);
        }
        4 => {
            // Delete or swap lines.
            let starts = line_starts(data);
            if starts.len() < 2 {
                return;
            }
            let i = rng.below(starts.len() - 1);
            let line = data[starts[i]..starts[i + 1]].to_vec();
            data.drain(starts[i]..starts[i + 1]);
            if rng.chance(2) {
                let starts = line_starts(data);
                let at = *rng.pick(&starts);
                data.splice(at..at, line);
            }
        }
        5 => {
            // Separators and line ends the two parsers might split differently.
            if data.is_empty() {
                return;
            }
            let i = rng.below(data.len());
            const SEPARATORS: &[&[u8]] = &[
                b"\r\n",
                b"\r",
                b"\t",
                b"\x0b",
                b"\x0c",
                "\u{a0}".as_bytes(),
                "\u{2003}".as_bytes(),
                b"/",
                b"//",
                b" ",
                b"\\\n",
                b"#",
            ];
            let with = *rng.pick(SEPARATORS);
            data.splice(i..i + 1, with.iter().copied());
        }
        _ => {
            // Change a keyword.
            let starts = line_starts(data);
            let at = *rng.pick(&starts);
            const KEYWORDS: &[&[u8]] = &[b"l ", b"p ", b"f ", b"v ", b"vt ", b"vn ", b"o "];
            let keyword = *rng.pick(KEYWORDS);
            data.splice(at..at, keyword.iter().copied());
        }
    }
}

/// An `f` line of 1–6 corners with random (often extreme) indices and random slash layouts.
fn random_face(rng: &mut Rng) -> String {
    let corners = 1 + rng.below(6);
    let index = |rng: &mut Rng| -> String {
        match rng.below(4) {
            0 => rng.pick(NUMBERS).to_string(),
            1 => format!("-{}", 1 + rng.below(8)),
            _ => format!("{}", 1 + rng.below(8)),
        }
    };
    let mut line = String::from(if rng.chance(5) { "l" } else { "f" });
    for _ in 0..corners {
        let (v, t, n) = (index(rng), index(rng), index(rng));
        let corner = match rng.below(6) {
            0 => v,
            1 => format!("{v}/{t}"),
            2 => format!("{v}//{n}"),
            _ => format!("{v}/{t}/{n}"),
        };
        line.push(' ');
        line.push_str(&corner);
    }
    line
}
