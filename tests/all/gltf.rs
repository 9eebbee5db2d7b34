//! `--model FILE.gltf` / `.glb`: glTF 2.0 models, and tests shaped like Khronos' NormalTangentTest
//! and NormalTangentMirrorTest. The fixtures are written here: a 2 × 2 grid of cells, one per UV
//! orientation (as drawn, mirrored U, mirrored V, both: turned by 180°), each a real bump of
//! geometry beside a flat quad whose normal map is baked from that bump; once without tangents and
//! once with them supplied (w = +1 where the UVs are not mirrored, −1 where they are).
//!
//! Khronos' models are judged by eye, each cell's two halves side by side. Here a second file has
//! every bump and quad swapped, so that each quad is drawn exactly where its bump was: the two
//! frames are compared cell by cell (same light, same pixels), which a side-by-side comparison under
//! a point light cannot do. The project's colour views are tangent-space vectors (light, eye, the
//! map's normal), which differ between a bump (flat map, tilted frame) and a quad (baked map, flat
//! frame) even when both are right, so the comparison is of the lit frame, under two lights.

use std::path::Path;

use image::RgbImage;

use crate::common;

/// The UV orientations of the cells: how a point (s, t) of a half (s right, t up, both 0..1) gets its
/// glTF UV (v down the picture), and the tangent-space axes T = dP/du and B = dP/d(picture up) there.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Orientation {
    Upright,
    MirroredU,
    MirroredV,
    Turned,
}

const ORIENTATIONS: [Orientation; 4] = [
    Orientation::Upright,
    Orientation::MirroredU,
    Orientation::MirroredV,
    Orientation::Turned,
];

impl Orientation {
    fn uv(self, s: f32, t: f32) -> [f32; 2] {
        match self {
            Orientation::Upright => [s, 1.0 - t],
            Orientation::MirroredU => [1.0 - s, 1.0 - t],
            Orientation::MirroredV => [s, t],
            Orientation::Turned => [1.0 - s, t],
        }
    }

    /// (s, t) of a picture point (u, v): the inverse of [`Orientation::uv`] (each is its own).
    fn st(self, u: f32, v: f32) -> [f32; 2] {
        self.uv(u, v)
    }

    /// T and B in the quad's plane (x right, y up), as signs.
    fn axes(self) -> (f32, f32) {
        match self {
            Orientation::Upright => (1.0, 1.0),
            Orientation::MirroredU => (-1.0, 1.0),
            Orientation::MirroredV => (1.0, -1.0),
            Orientation::Turned => (-1.0, -1.0),
        }
    }

    /// The handedness a file gives: the sign of B against cross(N, T).
    fn w(self) -> f32 {
        let (t, b) = self.axes();
        t * b
    }
}

/// The bump's height over a half: a raised cosine of radius 0.4 in the middle.
const BUMP_HEIGHT: f32 = 0.12;
const BUMP_RADIUS: f32 = 0.4;

fn height(s: f32, t: f32) -> f32 {
    let r = ((s - 0.5).powi(2) + (t - 0.5).powi(2)).sqrt();
    if r >= BUMP_RADIUS {
        return 0.0;
    }
    BUMP_HEIGHT * 0.5 * (1.0 + (std::f32::consts::PI * r / BUMP_RADIUS).cos())
}

/// The bump's unit normal at (s, t) (x right, y up, z out), from the height's slope.
fn bump_normal(s: f32, t: f32) -> [f32; 3] {
    let e = 1e-3;
    let dx = (height(s + e, t) - height(s - e, t)) / (2.0 * e);
    let dy = (height(s, t + e) - height(s, t - e)) / (2.0 * e);
    let l = (dx * dx + dy * dy + 1.0).sqrt();
    [-dx / l, -dy / l, 1.0 / l]
}

/// The normal map of `orientation`'s quad, baked from the bump: each texel the bump's normal at the
/// point it is drawn on, in the quad's T, B, N. PNG, `size²`, green up.
fn baked_map(orientation: Orientation, size: u32) -> RgbImage {
    let (tx, by) = orientation.axes();
    RgbImage::from_fn(size, size, |x, y| {
        let (u, v) = (
            (x as f32 + 0.5) / size as f32,
            (y as f32 + 0.5) / size as f32,
        );
        let [s, t] = orientation.st(u, v);
        let [nx, ny, nz] = bump_normal(s, t);
        let c = |v: f32| (127.5 * (v + 1.0)).round().clamp(0.0, 255.0) as u8;
        image::Rgb([c(nx * tx), c(ny * by), c(nz)])
    })
}

/// A glTF's binary buffer being written: each array a view and an accessor.
#[derive(Default)]
pub struct Buffers {
    pub bin: Vec<u8>,
    pub views: Vec<String>,
    pub accessors: Vec<String>,
}

impl Buffers {
    /// Floats, `width` per element (`kind`: "VEC2", "VEC3", "VEC4"); min and max given for
    /// POSITION as the specification asks.
    pub fn floats(&mut self, data: &[f32], width: usize, kind: &str, bounds: bool) -> usize {
        self.view(data.iter().flat_map(|v| v.to_le_bytes()));
        let count = data.len() / width;
        let mut extra = String::new();
        if bounds {
            let (mut min, mut max) = (vec![f32::MAX; width], vec![f32::MIN; width]);
            for e in data.chunks(width) {
                for k in 0..width {
                    min[k] = min[k].min(e[k]);
                    max[k] = max[k].max(e[k]);
                }
            }
            extra = format!(r#","min":{min:?},"max":{max:?}"#);
        }
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":5126,"count":{count},"type":"{kind}"{extra}}}"#,
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }

    /// The bytes at the end of the buffer, as a new view.
    fn view(&mut self, bytes: impl Iterator<Item = u8>) {
        let offset = self.bin.len();
        self.bin.extend(bytes);
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{}}}"#,
            self.bin.len() - offset
        ));
    }

    fn indices(&mut self, data: &[u32]) -> usize {
        self.view(data.iter().flat_map(|v| v.to_le_bytes()));
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":5125,"count":{},"type":"SCALAR"}}"#,
            self.views.len() - 1,
            data.len()
        ));
        self.accessors.len() - 1
    }
}

/// One primitive's arrays, and its material.
struct Part {
    positions: Vec<f32>,
    normals: Vec<f32>,
    uvs: Vec<f32>,
    tangents: Vec<f32>,
    indices: Vec<u32>,
    material: usize,
}

/// A half at `x0, y0` (1 × 1, facing +z): the bump as a grid of `n²` quads, or a flat quad.
fn half(orientation: Orientation, x0: f32, y0: f32, bump: bool, material: usize) -> Part {
    let n = if bump { 48 } else { 1 };
    let mut part = Part {
        positions: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        tangents: Vec::new(),
        indices: Vec::new(),
        material,
    };
    let (tx, _) = orientation.axes();
    for j in 0..=n {
        for i in 0..=n {
            let (s, t) = (i as f32 / n as f32, j as f32 / n as f32);
            let (h, normal) = match bump {
                true => (height(s, t), bump_normal(s, t)),
                false => (0.0, [0.0, 0.0, 1.0]),
            };
            part.positions.extend([x0 + s, y0 + t, h]);
            part.normals.extend(normal);
            part.uvs.extend(orientation.uv(s, t));
            // T along ±x, made orthogonal to the normal.
            let [nx, ny, nz] = normal;
            let d = tx * nx;
            let tangent = [tx - d * nx, -d * ny, -d * nz];
            let l = tangent.iter().map(|v| v * v).sum::<f32>().sqrt();
            part.tangents
                .extend(tangent.map(|v| v / l).into_iter().chain([orientation.w()]));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let k = j * (n + 1) + i;
            let [a, b, c, d] = [k, k + 1, k + n + 2, k + n + 1].map(|v| v as u32);
            part.indices.extend([a, b, c, a, c, d]);
        }
    }
    part
}

/// How a fixture's buffer is stored.
#[derive(Clone, Copy, PartialEq)]
enum Storage {
    /// A data URI in the JSON.
    DataUri,
    /// A `.bin` file beside it.
    File,
}

/// Which halves' primitives carry a `TANGENT`.
#[derive(Clone, Copy, PartialEq)]
enum Supplied {
    All,
    None,
    /// The bumps' primitives only: the flat quads' tangents are the viewer's to compute.
    Bumps,
}

/// Writes `name`.gltf in `dir`: the 2 × 2 grid of cells, bumps left (or right, `swapped`), with
/// tangents where `tangents` says, the baked maps as PNG files beside it.
fn write_cells(dir: &Path, name: &str, swapped: bool, tangents: Supplied, storage: Storage) {
    for (k, o) in ORIENTATIONS.iter().enumerate() {
        baked_map(*o, 256)
            .save(dir.join(format!("baked{k}.png")))
            .unwrap();
    }
    let mut parts = Vec::new();
    for (k, &o) in ORIENTATIONS.iter().enumerate() {
        let (x0, y0) = ((k % 2) as f32 * 2.4, (k / 2) as f32 * -1.2);
        let (bump_x, quad_x) = match swapped {
            false => (x0, x0 + 1.1),
            true => (x0 + 1.1, x0),
        };
        parts.push((half(o, bump_x, y0, true, 0), tangents != Supplied::None));
        parts.push((half(o, quad_x, y0, false, k + 1), tangents == Supplied::All));
    }
    let mut buffers = Buffers::default();
    let mut primitives = Vec::new();
    for (p, with_tangents) in &parts {
        let position = buffers.floats(&p.positions, 3, "VEC3", true);
        let normal = buffers.floats(&p.normals, 3, "VEC3", false);
        let uv = buffers.floats(&p.uvs, 2, "VEC2", false);
        let mut attributes =
            format!(r#""POSITION":{position},"NORMAL":{normal},"TEXCOORD_0":{uv}"#);
        if *with_tangents {
            let tangent = buffers.floats(&p.tangents, 4, "VEC4", false);
            attributes += &format!(r#","TANGENT":{tangent}"#);
        }
        let indices = buffers.indices(&p.indices);
        primitives.push(format!(
            r#"{{"attributes":{{{attributes}}},"indices":{indices},"material":{}}}"#,
            p.material
        ));
    }
    // Dark diffuse: the tutorial's light would saturate a light one, and saturation hides relief.
    let base = r#""pbrMetallicRoughness":{"baseColorFactor":[0.25,0.25,0.25,1]}"#;
    let mut materials = vec![format!(r#"{{"name":"bump",{base}}}"#)];
    for k in 0..4 {
        materials.push(format!(
            r#"{{"name":"baked{k}",{base},"normalTexture":{{"index":{k}}}}}"#
        ));
    }
    let uri = match storage {
        Storage::DataUri => format!(
            "data:application/octet-stream;base64,{}",
            tutorial13::model::gltf::encode_base64(&buffers.bin)
        ),
        Storage::File => {
            std::fs::write(dir.join(format!("{name}.bin")), &buffers.bin).unwrap();
            format!("{name}.bin")
        }
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0","generator":"tutorial13 tests"}},"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{}]}}],"materials":[{}],
"textures":[{}],"images":[{}],
"buffers":[{{"uri":"{uri}","byteLength":{}}}],"bufferViews":[{}],"accessors":[{}]}}"#,
        primitives.join(","),
        materials.join(","),
        (0..4)
            .map(|k| format!(r#"{{"source":{k}}}"#))
            .collect::<Vec<_>>()
            .join(","),
        (0..4)
            .map(|k| format!(r#"{{"uri":"baked{k}.png"}}"#))
            .collect::<Vec<_>>()
            .join(","),
        buffers.bin.len(),
        buffers.views.join(","),
        buffers.accessors.join(",")
    );
    std::fs::write(dir.join(format!("{name}.gltf")), json).unwrap();
}

/// The binary's headless frame of `model` with `args`.
fn shot(dir: &Path, model: &str, out: &str, args: &[&str]) -> (RgbImage, String) {
    let run = common::run(
        common::tutorial13()
            .args(["--headless", "--model", model, "--screenshot", out])
            .args(args)
            .current_dir(dir),
    );
    let stderr = common::text(&run.stderr);
    assert!(run.status.success(), "{model} {args:?}: {stderr}");
    (image::open(dir.join(out)).unwrap().into_rgb8(), stderr)
}

/// The two lights (in the files' coordinates): above left and in front, below right and in front.
const LIGHTS: [&str; 2] = ["--light=-1,3,3", "--light=5,-4,2.5"];

/// Per cell (in [`ORIENTATIONS`] order): the mean and the 99th percentile of the per-pixel largest
/// channel difference between the frames of the two files, over the pixels both draw in the
/// cell's two halves, each light and `args` (a tangent source).
fn cell_differences(dir: &Path, names: [&str; 2], args: &[&str]) -> Vec<(f64, u8)> {
    let mut per_cell = vec![Vec::new(); 4];
    for (l, light) in LIGHTS.iter().enumerate() {
        let mut all_args = vec![*light];
        all_args.extend(args);
        let tag = args.join("").replace(['-', ' '], "");
        let frames = names.map(|n| {
            shot(
                dir,
                &format!("{n}.gltf"),
                &format!("{n}-{tag}-{l}.png"),
                &all_args,
            )
            .0
        });
        let (w, h) = frames[0].dimensions();
        // Cells by where they are drawn: the grid's four quadrants of the drawn area.
        let drawn = |x, y| !common::is_background(frames[0].get_pixel(x, y));
        let xs: Vec<u32> = (0..w).filter(|&x| (0..h).any(|y| drawn(x, y))).collect();
        let ys: Vec<u32> = (0..h).filter(|&y| (0..w).any(|x| drawn(x, y))).collect();
        let (x_mid, y_mid) = (
            (xs[0] + xs[xs.len() - 1]) / 2,
            (ys[0] + ys[ys.len() - 1]) / 2,
        );
        for y in 0..h {
            for x in 0..w {
                let [a, b] = [0, 1].map(|f| *frames[f].get_pixel(x, y));
                if common::is_background(&a) || common::is_background(&b) {
                    continue;
                }
                let cell = usize::from(x > x_mid) + 2 * usize::from(y > y_mid);
                let d = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap();
                per_cell[cell].push(d);
            }
        }
    }
    per_cell
        .into_iter()
        .map(|mut d| {
            d.sort_unstable();
            let mean = d.iter().map(|&v| v as f64).sum::<f64>() / d.len().max(1) as f64;
            (mean, d[d.len() * 99 / 100])
        })
        .collect()
}

/// How close a right frame's halves must be: the mean of the largest channel difference per pixel,
/// and its 99th percentile. What remains when the frame is right is the bump's parallax (its
/// raised pixels are seen a little off where the flat quad's are) and 8-bit maps.
const MEAN_TOLERANCE: f64 = 3.0;
const P99_TOLERANCE: u8 = 28;

fn within(d: &[(f64, u8)]) -> bool {
    d.iter()
        .all(|&(mean, p99)| mean <= MEAN_TOLERANCE && p99 <= P99_TOLERANCE)
}

fn show(label: &str, d: &[(f64, u8)]) -> String {
    let cells: Vec<String> = ORIENTATIONS
        .iter()
        .zip(d)
        .map(|(o, (mean, p99))| format!("{o:?} mean {mean:.2} p99 {p99}"))
        .collect();
    format!("{label}: {}", cells.join(" | "))
}

// Fails if a glTF's supplied tangents (w = +1 and −1) are not used as the bitangent's sign (the
// mirrored cells' relief comes out inverted), if MikkTSpace is not computed on the UVs as glTF
// stores them turned up the picture (every cell inverted in green), if V is negated the tutorial's
// way, or if the normal texture, the node or the data-URI and side-by-side buffers are misread, or
// if a file whose bumps alone carry tangents is drawn wrong: each cell's bump and its baked quad,
// drawn in the same place, must shade alike within the stated tolerance. Also measures, for docs/model.md, what the tutorial's frame does there with and without
// its handedness fix, and holds those findings (they change only if the tutorial's frame does).
#[test]
fn normal_tangent_cells_shade_like_their_bumps() {
    let dir = common::scratch("gltf_cells");
    write_cells(&dir, "with", false, Supplied::All, Storage::File);
    write_cells(&dir, "with-swapped", true, Supplied::All, Storage::DataUri);
    write_cells(&dir, "without", false, Supplied::None, Storage::DataUri);
    write_cells(&dir, "without-swapped", true, Supplied::None, Storage::File);
    write_cells(&dir, "bumps", false, Supplied::Bumps, Storage::File);
    write_cells(
        &dir,
        "bumps-swapped",
        true,
        Supplied::Bumps,
        Storage::DataUri,
    );
    let supplied = ["with", "with-swapped"];
    let generated = ["without", "without-swapped"];

    let file = cell_differences(&dir, supplied, &[]);
    let mikk_generated = cell_differences(&dir, generated, &[]);
    let mixed = cell_differences(&dir, ["bumps", "bumps-swapped"], &[]);
    let mikk_supplied = cell_differences(&dir, supplied, &["--tangents", "mikktspace"]);
    let tutorial = |extra: &[&'static str]| {
        let mut args = vec!["--tangents", "tutorial"];
        args.extend(extra);
        cell_differences(&dir, generated, &args)
    };
    let summed = tutorial(&[]);
    let summed_no_fix = tutorial(&["--no-handedness"]);
    let normalized = tutorial(&["--normalize-tbn"]);
    let normalized_no_fix = tutorial(&["--normalize-tbn", "--no-handedness"]);
    let report = [
        show("file tangents", &file),
        show("no tangents (MikkTSpace)", &mikk_generated),
        show("bumps' tangents, quads' MikkTSpace", &mixed),
        show("MikkTSpace over supplied", &mikk_supplied),
        show("tutorial, TBN as summed, handedness fix", &summed),
        show("tutorial, TBN as summed, no handedness fix", &summed_no_fix),
        show("tutorial, TBN normalized, handedness fix", &normalized),
        show(
            "tutorial, TBN normalized, no handedness fix",
            &normalized_no_fix,
        ),
    ]
    .join("\n");
    println!("{report}");
    for (label, d) in [
        ("file", &file),
        ("mikktspace (none supplied)", &mikk_generated),
        ("file tangents on the bumps only", &mixed),
        ("mikktspace (over supplied)", &mikk_supplied),
    ] {
        assert!(within(d), "{label} out of tolerance:\n{report}");
    }
    // The findings docs/model.md states: the tutorial's summed frame is off everywhere (its T and
    // B are not unit length); normalized, it is right where the UVs are not mirrored, and its
    // handedness fix turns T the wrong way on the singly mirrored cells.
    assert!(!within(&summed), "{report}");
    assert!(within(&normalized_no_fix), "{report}");
    let [upright, mirrored_u, mirrored_v, turned] =
        [0, 1, 2, 3].map(|k| within(&normalized[k..=k]));
    assert!(upright && turned && !mirrored_u && !mirrored_v, "{report}");
}

// Fails if a primitive's own tangents are dropped because another primitive has none (they were:
// all or nothing), if the primitives without get anything but MikkTSpace's, or if the runs of
// triangles without are misplaced: drawn from the file's tangents, the bumps (which carry them) must
// keep them to the bit and the quads (which do not) must have MikkTSpace's of the quads alone.
#[test]
fn primitives_without_tangents_get_mikktspace_the_others_keep_the_files() {
    use tutorial13::mesh::MeshOptions;
    use tutorial13::tangent_source::{mikktspace_tangents, welded_mesh, TangentSource};

    let dir = common::scratch("gltf_mixed_tangents");
    write_cells(&dir, "bumps", false, Supplied::Bumps, Storage::File);
    write_cells(&dir, "with", false, Supplied::All, Storage::File);
    let load = |name: &str| {
        let path = dir.join(format!("{name}.gltf"));
        tutorial13::model::load_model(&path, &Default::default()).unwrap()
    };
    let (mixed, with) = (load("bumps"), load("with"));
    assert_eq!(mixed.soup, with.soup);
    // The quads are the four baked materials' triangles (the bumps are material 0).
    let quads: Vec<std::ops::Range<usize>> = mixed
        .ranges
        .iter()
        .filter(|r| r.material != 0)
        .map(|r| r.triangles.clone())
        .collect();
    assert_eq!(quads.len(), 4);
    let file = mixed
        .file_tangents
        .as_ref()
        .expect("the bumps' tangents kept");
    let quads_in_one_run = quads[0].start..quads[3].end;
    assert_eq!(file.missing, [quads_in_one_run]);
    assert!(
        mixed.notices.iter().any(|n| n.contains(
            "some primitives have no TANGENT: MikkTSpace is computed for those, the others keep the file's"
        )),
        "{:?}",
        mixed.notices
    );

    let mut quad_soup = tutorial13::common::objloader::TriangleSoup::default();
    for r in &quads {
        let corners = 3 * r.start..3 * r.end;
        quad_soup
            .vertices
            .extend(&mixed.soup.vertices[corners.clone()]);
        quad_soup.uvs.extend(&mixed.soup.uvs[corners.clone()]);
        quad_soup.normals.extend(&mixed.soup.normals[corners]);
    }
    let quad_tangents = mikktspace_tangents(&quad_soup).unwrap();
    let mut expected = with.file_tangents.clone().unwrap().per_corner;
    let mut from = 0;
    for r in &quads {
        let to = from + 3 * r.len();
        expected[3 * r.start..3 * r.end].copy_from_slice(&quad_tangents[from..to]);
        from = to;
    }
    let options = MeshOptions::default();
    let drawn = TangentSource::File
        .mesh_with(&mixed.soup, Some(file), options)
        .unwrap();
    let predicted = welded_mesh(&mixed.soup, &expected);
    assert_eq!(common::mesh_bit_difference(&drawn, &predicted), None);
    // MikkTSpace over every primitive (what the file got before) differs on the bumps.
    let everywhere = TangentSource::MikkTSpace
        .mesh(&mixed.soup, options)
        .unwrap();
    assert!(common::mesh_bit_difference(&drawn, &everywhere).is_some());
}

/// A 2 × 2 quad facing +z with UVs upright (the picture's top row at the quad's top), a diffuse
/// map (image 0, `image`: `"uri":"…"` or `"bufferView":N,"mimeType":"image/png"`) and no normal
/// map: the JSON (buffer 0 at `buffer_uri`, or the GLB's BIN chunk when `None`) and the binary.
fn quad_document(buffer_uri: Option<&str>, png: Option<&[u8]>) -> (String, Vec<u8>) {
    quad_document_with_uvs(buffer_uri, png, 0)
}

/// [`quad_document`] with its picture laid by `TEXCOORD_set`: for set 1, TEXCOORD_0 is there too,
/// turned upside down, and `baseColorTexture` names set 1.
fn quad_document_with_uvs(
    buffer_uri: Option<&str>,
    png: Option<&[u8]>,
    set: u32,
) -> (String, Vec<u8>) {
    let mut buffers = Buffers::default();
    let position = buffers.floats(
        &[
            -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
        ],
        3,
        "VEC3",
        true,
    );
    let normal = buffers.floats(&[0.0, 0.0, 1.0].repeat(4), 3, "VEC3", false);
    let upright = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let mut uvs = format!(
        r#""TEXCOORD_{set}":{}"#,
        buffers.floats(&upright, 2, "VEC2", false)
    );
    if set != 0 {
        let upside_down = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
        let uv0 = buffers.floats(&upside_down, 2, "VEC2", false);
        uvs += &format!(r#","TEXCOORD_0":{uv0}"#);
    }
    let indices = buffers.indices(&[0, 1, 2, 0, 2, 3]);
    let image = match png {
        Some(png) => {
            buffers.view(png.iter().copied());
            format!(
                r#""bufferView":{},"mimeType":"image/png""#,
                buffers.views.len() - 1
            )
        }
        None => r#""uri":"picture.png""#.to_string(),
    };
    let uri = buffer_uri.map_or(String::new(), |u| format!(r#""uri":"{u}","#));
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal},{uvs}}},"indices":{indices},"material":0}}]}}],
"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0,"texCoord":{set}}}}}}}],
"textures":[{{"source":0}}],"images":[{{{image}}}],
"buffers":[{{{uri}"byteLength":{}}}],"bufferViews":[{}],"accessors":[{}]}}"#,
        buffers.bin.len(),
        buffers.views.join(","),
        buffers.accessors.join(",")
    );
    (json, buffers.bin)
}

/// A binary glTF: the 12-byte header, the JSON chunk, the BIN chunk, each padded to 4 bytes.
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// A picture red in its top half and blue in its bottom half.
fn top_red_png() -> Vec<u8> {
    let image = RgbImage::from_fn(32, 32, |_, y| match y < 16 {
        true => image::Rgb([220, 30, 30]),
        false => image::Rgb([30, 30, 220]),
    });
    let mut png = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    png
}

// Fails if a glTF's picture is drawn upside down (V read as an OBJ's, or negated the tutorial's
// way), if a .glb's BIN chunk, an image in a buffer view, a .gltf's buffer file or its image file
// beside it is not read, or if a material naming TEXCOORD_1 is laid with TEXCOORD_0 (there upside
// down): that frame must be the TEXCOORD_0 file's, bit for bit. Also fails if two UV sets or a
// clamping sampler go unsaid.
//
// Upright is read off two pixels of one column, a quarter of the quad's height below its top and
// above its bottom: red must exceed blue by 32 or more in the first, blue red in the second
// (computed in i16, not in u8, which would wrap or overflow). The picture's halves are (220, 30, 30)
// and (30, 30, 220), but the default light washes the quad out towards white, and its specular
// highlight, (255, 255, 255), covers the middle of the lower half, where neither check could hold.
// So the column is an eighth of the quad's width from its left edge, out of the highlight, where
// the pixels are (255, 123, 123) and (200, 200, 255): margins of 132 and 55. With the picture
// upside down (its rows or its V flipped) both differences are negative there, and both checks fail.
#[test]
fn a_gltf_picture_is_upright() {
    let dir = common::scratch("gltf_upright");
    let png = top_red_png();
    let (json, bin) = quad_document(None, Some(&png));
    std::fs::write(dir.join("quad.glb"), glb(&json, &bin)).unwrap();
    let (json, bin) = quad_document(Some("quad.bin"), None);
    std::fs::write(dir.join("quad.gltf"), json).unwrap();
    std::fs::write(dir.join("quad.bin"), bin).unwrap();
    std::fs::write(dir.join("picture.png"), &png).unwrap();
    let (json, bin) = quad_document_with_uvs(None, Some(&png), 1);
    std::fs::write(dir.join("quad-set1.glb"), glb(&json, &bin)).unwrap();
    let mut frames = Vec::new();
    for model in ["quad.glb", "quad.gltf", "quad-set1.glb"] {
        let (frame, stderr) = shot(&dir, model, &format!("{model}.png"), &[]);
        assert!(stderr.contains("metallic-roughness"), "{stderr}");
        let (mid_x, mid_y) = (frame.width() / 2, frame.height() / 2);
        let row: Vec<u32> = (0..frame.width())
            .filter(|&x| !common::is_background(frame.get_pixel(x, mid_y)))
            .collect();
        let column: Vec<u32> = (0..frame.height())
            .filter(|&y| !common::is_background(frame.get_pixel(mid_x, y)))
            .collect();
        assert!(!row.is_empty() && !column.is_empty(), "{model}: no quad");
        let (left, right) = (row[0], row[row.len() - 1]);
        let (top, bottom) = (column[0], column[column.len() - 1]);
        let x = left + (right - left) / 8;
        let (upper, lower) = (
            *frame.get_pixel(x, top + (bottom - top) / 4),
            *frame.get_pixel(x, bottom - (bottom - top) / 4),
        );
        // How far one channel is above another, in i16: no u8 arithmetic to wrap or overflow.
        let above = |p: image::Rgb<u8>, a: usize, b: usize| i16::from(p[a]) - i16::from(p[b]);
        assert!(
            above(upper, 0, 2) >= 32,
            "{model}: upper half at x = {x} is not red: {upper:?}"
        );
        assert!(
            above(lower, 2, 0) >= 32,
            "{model}: lower half at x = {x} is not blue: {lower:?}"
        );
        frames.push(frame);
    }
    // Laid by TEXCOORD_1, the picture is exactly where TEXCOORD_0 lays it in the others.
    assert!(frames[2] == frames[0], "TEXCOORD_1's frame differs");
    // Two maps on two sets: the program says which one it reads both with.
    let (json, bin) = quad_document_with_uvs(None, Some(&png), 1);
    let material = r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":1}}}"#;
    assert!(json.contains(material));
    let json = json.replace(
        material,
        r#"{"normalTexture":{"index":0,"texCoord":1},"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}"#,
    );
    std::fs::write(dir.join("two-sets.glb"), glb(&json, &bin)).unwrap();
    let (_, stderr) = shot(&dir, "two-sets.glb", "two-sets.png", &[]);
    let said = "baseColorTexture uses TEXCOORD_0, normalTexture TEXCOORD_1: both are read with \
                TEXCOORD_1, the normal map's";
    assert!(stderr.contains(said), "{stderr}");
    // A sampler that clamps: said, and (UVs within 0..1) the same frame.
    let (json, bin) = quad_document(None, Some(&png));
    let texture = r#""textures":[{"source":0}]"#;
    assert!(json.contains(texture));
    let json = json.replace(
        texture,
        r#""samplers":[{"wrapS":33071}],"textures":[{"source":0,"sampler":0}]"#,
    );
    std::fs::write(dir.join("clamped.glb"), glb(&json, &bin)).unwrap();
    let (frame, stderr) = shot(&dir, "clamped.glb", "clamped.png", &[]);
    let said = "baseColorTexture of 'material 0''s sampler asks for ClampToEdge on S: sampled \
                with Repeat";
    assert!(stderr.contains(said), "{stderr}");
    assert!(frame == frames[0], "the clamped quad's frame differs");
}

// Fails if a bad glTF draws, panics, or fails with anything but one line naming the file and the
// reason and exit status 1, or if a screenshot is written: a .glb cut short, broken JSON, an
// accessor past its buffer, a missing buffer or image, a PNG cut short, lines instead of
// triangles, no UVs, no TEXCOORD_1 where the material names it, KHR_texture_transform.
#[test]
fn bad_gltf_files_are_one_line_errors() {
    let dir = common::scratch("gltf_bad");
    let png = top_red_png();
    std::fs::write(dir.join("picture.png"), &png).unwrap();
    let (json, bin) = quad_document(Some("quad.bin"), None);
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    std::fs::write(dir.join("garbled.png"), &png[..png.len() / 2]).unwrap();
    let (glb_json, glb_bin) = quad_document(None, Some(&png));
    let whole = glb(&glb_json, &glb_bin);
    let edit = |from: &str, to: &str| {
        assert!(json.contains(from), "{from}");
        json.replacen(from, to, 1).into_bytes()
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "cut.glb",
            whole[..whole.len() - 100].to_vec(),
            "binary glTF",
        ),
        (
            "broken.gltf",
            json.as_bytes()[..json.len() / 2].to_vec(),
            "JSON",
        ),
        (
            "range.gltf",
            edit(r#""count":4,"type":"VEC3""#, r#""count":400,"type":"VEC3""#),
            "out of range",
        ),
        ("buffer.gltf", edit("quad.bin", "gone.bin"), "gone.bin"),
        ("image.gltf", edit("picture.png", "gone.png"), "gone.png"),
        (
            "garbled.gltf",
            edit("picture.png", "garbled.png"),
            "garbled.png",
        ),
        (
            "lines.gltf",
            edit(r#""material":0"#, r#""material":0,"mode":1"#),
            "Lines",
        ),
        ("no-uvs.gltf", edit(r#","TEXCOORD_0":2"#, ""), "TEXCOORD_0"),
        (
            "no-set-1.gltf",
            edit(r#""index":0,"texCoord":0"#, r#""index":0,"texCoord":1"#),
            "no TEXCOORD_1, the UV set its material's maps name",
        ),
        (
            "transform.gltf",
            edit(
                r#"{"asset""#,
                r#"{"extensionsUsed":["KHR_texture_transform"],"asset""#,
            ),
            "KHR_texture_transform",
        ),
    ];
    for (name, bytes, reason) in cases {
        std::fs::write(dir.join(name), bytes).unwrap();
        let out = common::run(
            common::tutorial13()
                .args(["--headless", "--model", name, "--screenshot", "x.png"])
                .current_dir(&dir),
        );
        let stderr = common::text(&out.stderr);
        println!("{name}: {stderr}");
        assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
        assert!(
            stderr.contains(name) && stderr.contains(reason),
            "{name}: no '{reason}' in {stderr}"
        );
        assert!(!dir.join("x.png").exists(), "{name}");
    }
}
