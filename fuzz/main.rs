//! The fuzz harness's long runs, on the stable toolchain:
//!
//!     cargo run -p tutorial13-fuzz --profile fuzz -- --seconds 1800
//!
//! Options: `--seconds N` (total, shared equally by the targets; default 60), `--target NAME`
//! (obj, dds, bmp, pipeline, heightmap, model, photo, obj-tobj, lights, gltf, mikktspace, bake or
//! cage; repeatable; default all), `--seed N` (default: from the clock,
//! printed), `--slow-ms N` (a case slower than this fails; default 2000), `--replay FILE` (run one
//! input on the target named before it, else the one its folder is named after, and print the
//! outcome), `--make-corpus` (rewrite the seed
//! corpus in fuzz/corpus/ and exit). Failing inputs are saved to fuzz/regressions/<target>/,
//! which `cargo test` replays. Exit status 1 if anything failed.

#[path = "../tests/support/differential.rs"]
mod differential;
mod harness;
#[path = "../tests/support/mikktspace_reference.rs"]
mod mikktspace_reference;

use std::time::{Duration, Instant};

use harness::{fuzz, Target, TARGETS};

fn main() {
    let mut seconds = 60u64;
    let mut targets = Vec::new();
    let mut seed = None;
    let mut slow_ms = 2000u64;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = |name: &str| {
            args.next()
                .unwrap_or_else(|| usage(&format!("{name} needs a value")))
        };
        match arg.as_str() {
            "--seconds" => seconds = parse(&value("--seconds")),
            "--seed" => seed = Some(parse(&value("--seed"))),
            "--slow-ms" => slow_ms = parse(&value("--slow-ms")),
            "--target" => {
                let name = value("--target");
                targets.push(
                    Target::from_name(&name)
                        .unwrap_or_else(|| usage(&format!("unknown target {name}"))),
                );
            }
            "--replay" => {
                // One input, the full outcome, for the target given before it, else the one its
                // folder is named after (fuzz/regressions/<target>/...), else pipeline.
                let path = value("--replay");
                let bytes = std::fs::read(&path).unwrap_or_else(|e| usage(&format!("{path}: {e}")));
                let folder = std::path::Path::new(&path)
                    .parent()
                    .and_then(|dir| dir.file_name())
                    .and_then(|name| Target::from_name(&name.to_string_lossy()));
                let target = targets
                    .last()
                    .copied()
                    .or(folder)
                    .unwrap_or(Target::Pipeline);
                let outcome = harness::run_case(target, &bytes, Duration::from_millis(slow_ms));
                println!("{}: {path}: {outcome:?}", target.name());
                std::process::exit(i32::from(matches!(outcome, harness::Outcome::Failed(_))));
            }
            "--make-corpus" => {
                make_corpus();
                return;
            }
            other => usage(&format!("unknown argument {other}")),
        }
    }
    if targets.is_empty() {
        targets = TARGETS.to_vec();
    }
    let seed = seed.unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos() as u64)
            .unwrap_or(1)
    });
    // Without its seeds a target mutates only empty input, finds nothing and says so quietly (as
    // it did once, reading a folder that was not there): refuse to start instead.
    for &target in &targets {
        for dir in harness::seed_dirs(target) {
            if !dir.is_dir() {
                usage(&format!(
                    "no seeds for {}: {} is not a folder",
                    target.name(),
                    dir.display()
                ));
            }
        }
    }
    // Panics are expected and reported by the harness: keep stderr for the summary.
    std::panic::set_hook(Box::new(|_| {}));
    let share = Duration::from_secs(seconds) / targets.len() as u32;
    println!(
        "fuzz: seed {seed}, {seconds} s over {} target(s)",
        targets.len()
    );
    let mut failed = false;
    for target in targets {
        let start = Instant::now();
        let stats = fuzz(
            target,
            seed,
            Duration::from_millis(slow_ms),
            Some(&harness::regressions_dir(target)),
            |_| start.elapsed() >= share,
        );
        println!(
            "{:>8}: {} cases in {:.0} s ({} loaded, {} rejected), {} failure(s)",
            target.name(),
            stats.cases,
            start.elapsed().as_secs_f64(),
            stats.loaded,
            stats.rejected,
            stats.failures.len()
        );
        for f in &stats.failures {
            failed = true;
            let saved = f
                .saved
                .as_ref()
                .map(|p| p.display().to_string())
                .unwrap_or_else(|| "(not saved)".into());
            println!("          {} -> {saved}", f.message);
        }
    }
    std::process::exit(i32::from(failed));
}

fn parse(s: &str) -> u64 {
    s.parse()
        .unwrap_or_else(|_| usage(&format!("'{s}' is not a number")))
}

fn usage(problem: &str) -> ! {
    eprintln!(
        "fuzz: {problem}\nusage: fuzz [--seconds N] [--target obj|dds|bmp|pipeline|heightmap|model|photo|obj-tobj|lights|gltf|mikktspace|bake|cage]... [--seed N] [--slow-ms N] [--replay FILE] [--make-corpus]"
    );
    std::process::exit(2);
}

/// A light-directions file as capture sets ship them, with a comment and a blank line.
const LIGHTS_SEED: &str =
    "# x y z\n-0.0633 0.2921 0.9543\n\n0.1752 -0.4016 0.8988\n0.5 0.5 0.7071 # last\n";
/// A light-intensities file: three per line, and one value for all three.
const INTENSITIES_SEED: &str = "0.82 0.79 0.91\n1 1 1\n# dim\n0.5\n";

/// The seed corpus: small files made here (the tutorial's own files are not redistributable).
fn make_corpus() {
    use tutorial13::assets::obj_text::grid_cylinder_obj_text;
    use tutorial13::assets::{encode_bmp, encode_dds_dxt3};

    let write = |target: Target, name: &str, bytes: &[u8]| {
        let dir = harness::corpus_dir(target);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(name), bytes).unwrap();
    };
    let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n";
    write(
        Target::Obj,
        "triangle.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n",
    );
    write(
        Target::Obj,
        "quad.obj",
        format!("{quad}f 1/1/1 2/2/1 3/3/1 4/4/1\n").as_bytes(),
    );
    write(
        Target::Obj,
        "relative.obj",
        format!(
            "{quad}o a\nf -4/-4/-1 -3/-3/-1 -2/-2/-1\ng b\ns 1\nf -4/-4/-1 -2/-2/-1 -1/-1/-1\n"
        )
        .as_bytes(),
    );
    write(
        Target::Obj,
        "cylinder.obj",
        grid_cylinder_obj_text(6, 2, 1.0, 2.0, 1.0).as_bytes(),
    );
    write(
        Target::Obj,
        "shared-position.obj",
        b"v 0 0 0\nvt 0 0\nvt 0.5 0\nvt 0 0.5\nvt 0.005 0\nvn 0 0 1\nvn 0 1 0\nf 1/1/1 1/2/1 1/3/1\nf 1/4/2 1/1/1 1/2/2\nf 1/1/1 1/2/1 1/3/1\n",
    );
    write(
        Target::Obj,
        "large.obj",
        b"v 1e38 0 0\nv -1e38 3e38 0\nv 3e38 -1e38 1e38\nvt 0 0\nvt 1e-6 0\nvt 0 1e-6\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 2/2/1 3/3/1\n",
    );

    for (name, bytes) in gltf_seeds() {
        write(Target::Gltf, name, &bytes);
    }
    for (name, bytes) in mikktspace_seeds() {
        write(Target::Mikktspace, &name, &bytes);
    }

    for (name, side) in [("4x4", 4u32), ("8x8", 8)] {
        let rgba: Vec<u8> = (0..side * side * 4).map(|i| (i * 37 % 256) as u8).collect();
        let dxt3 = encode_dds_dxt3(rgba, side).unwrap();
        write(Target::Dds, &format!("dxt3-{name}.DDS"), &dxt3);
        // The same header as DXT5 (same block size) and DXT1 (half the data suffices).
        let mut dxt5 = dxt3.clone();
        dxt5[84..88].copy_from_slice(b"DXT5");
        write(Target::Dds, &format!("dxt5-{name}.DDS"), &dxt5);
        let mut dxt1 = dxt3;
        dxt1[84..88].copy_from_slice(b"DXT1");
        write(Target::Dds, &format!("dxt1-{name}.DDS"), &dxt1);
    }
    for side in [1u32, 3, 4] {
        let rgb: Vec<[u8; 3]> = (0..side * side)
            .map(|i| [i as u8, (i * 7) as u8, (i * 13) as u8])
            .collect();
        let bmp = encode_bmp(&rgb, side).unwrap();
        write(Target::Bmp, &format!("rgb-{side}x{side}.bmp"), &bmp);
        if side == 3 {
            // Top-down: negative height.
            let mut top_down = bmp.clone();
            let h = -(side as i32);
            top_down[22..26].copy_from_slice(&h.to_le_bytes());
            write(Target::Bmp, "rgb-3x3-top-down.bmp", &top_down);
        }
    }
    // Height maps: 8- and 16-bit grey PNG, colour PNG, grey BMP; odd sizes, one texel.
    let png = |image: image::DynamicImage| {
        let mut bytes = Vec::new();
        image
            .write_to(
                &mut std::io::Cursor::new(&mut bytes),
                image::ImageFormat::Png,
            )
            .unwrap();
        bytes
    };
    let grey = image::GrayImage::from_fn(5, 3, |x, y| image::Luma([(x * 50 + y * 20) as u8]));
    write(Target::Heightmap, "grey-5x3.png", &png(grey.into()));
    let deep =
        image::ImageBuffer::from_fn(3, 4, |x, y| image::Luma([(x * 20000 + y * 999) as u16]));
    write(
        Target::Heightmap,
        "grey16-3x4.png",
        &png(image::DynamicImage::ImageLuma16(deep)),
    );
    let rgb = image::RgbImage::from_fn(2, 2, |x, y| image::Rgb([x as u8 * 200, y as u8 * 90, 7]));
    write(Target::Heightmap, "rgb-2x2.png", &png(rgb.into()));
    let one = image::GrayImage::from_pixel(1, 1, image::Luma([128]));
    write(Target::Heightmap, "grey-1x1.png", &png(one.into()));
    let ramp: Vec<[u8; 3]> = (0..16u8).map(|i| [i * 16; 3]).collect();
    write(
        Target::Heightmap,
        "ramp-4x4.bmp",
        &encode_bmp(&ramp, 4).unwrap(),
    );
    // Photos: colour and grey JPEG (the format phones write), 16-bit PNG, TGA.
    let encoded = |image: image::DynamicImage, format| {
        let mut bytes = Vec::new();
        let mut cursor = std::io::Cursor::new(&mut bytes);
        image.write_to(&mut cursor, format).unwrap();
        bytes
    };
    let colour = image::RgbImage::from_fn(8, 6, |x, y| {
        image::Rgb([(x * 30) as u8, (y * 40) as u8, ((x + y) * 15) as u8])
    });
    let jpeg = image::ImageFormat::Jpeg;
    write(
        Target::Photo,
        "rgb-8x6.jpg",
        &encoded(colour.clone().into(), jpeg),
    );
    let grey = image::DynamicImage::from(colour.clone()).into_luma8();
    write(Target::Photo, "grey-8x6.jpg", &encoded(grey.into(), jpeg));
    write(Target::Lights, "directions.txt", LIGHTS_SEED.as_bytes());
    write(
        Target::Lights,
        "intensities.txt",
        INTENSITIES_SEED.as_bytes(),
    );
    let deep = image::ImageBuffer::from_fn(3, 2, |x, y| {
        image::Rgb([(x * 30000) as u16, (y * 60000) as u16, 65535])
    });
    let deep = image::DynamicImage::ImageRgb16(deep);
    write(
        Target::Photo,
        "rgb16-3x2.png",
        &encoded(deep, image::ImageFormat::Png),
    );
    let tga = image::ImageFormat::Tga;
    write(Target::Photo, "rgb-8x6.tga", &encoded(colour.into(), tga));
    println!(
        "fuzz: corpus written to {}",
        harness::fuzz_dir().join("corpus").display()
    );
}

/// A quad as glTF: JSON with its buffer as a data URI, with and without tangents, under a node
/// that moves and mirrors it; and the same as a binary `.glb` (its buffer in the BIN chunk).
fn gltf_seeds() -> Vec<(&'static str, Vec<u8>)> {
    let floats = |v: &[f32]| -> Vec<u8> { v.iter().flat_map(|f| f.to_le_bytes()).collect() };
    let mut bin = floats(&[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.]);
    bin.extend(floats(&[0., 0., 1.].repeat(4)));
    bin.extend(floats(&[0., 1., 1., 1., 1., 0., 0., 0.]));
    bin.extend(floats(&[1., 0., 0., -1.].repeat(4)));
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    let views = "[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},\
        {\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},\
        {\"buffer\":0,\"byteOffset\":96,\"byteLength\":32},\
        {\"buffer\":0,\"byteOffset\":128,\"byteLength\":64},\
        {\"buffer\":0,\"byteOffset\":192,\"byteLength\":12}]";
    let accessors = "[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\
        \"min\":[0,0,0],\"max\":[1,1,0]},\
        {\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},\
        {\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},\
        {\"bufferView\":3,\"componentType\":5126,\"count\":4,\"type\":\"VEC4\"},\
        {\"bufferView\":4,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]";
    let document = |tangent: &str, buffer: &str| {
        format!(
            "{{\"asset\":{{\"version\":\"2.0\"}},\"scene\":0,\"scenes\":[{{\"nodes\":[0]}}],\
             \"nodes\":[{{\"children\":[1],\"translation\":[2,0,0]}},{{\"mesh\":0,\"scale\":[-1,1,1]}}],\
             \"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":0,\"NORMAL\":1,\
             \"TEXCOORD_0\":2{tangent}}},\"indices\":4,\"material\":0}}]}}],\
             \"materials\":[{{\"normalTexture\":{{\"index\":0,\"scale\":2}}}}],\
             \"textures\":[{{\"source\":0}}],\"images\":[{{\"uri\":\"data:image/png;base64,\"}}],\
             \"buffers\":[{{{buffer}\"byteLength\":204}}],\"bufferViews\":{views},\
             \"accessors\":{accessors}}}"
        )
    };
    let uri = format!(
        "\"uri\":\"data:application/octet-stream;base64,{}\",",
        tutorial13::model::gltf::encode_base64(&bin)
    );
    let with = document(",\"TANGENT\":3", &uri);
    let without = document("", &uri);
    let mut json = document(",\"TANGENT\":3", "").into_bytes();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut glb = b"glTF".to_vec();
    for n in [2, total, json.len()] {
        glb.extend((n as u32).to_le_bytes());
    }
    glb.extend(b"JSON");
    glb.extend(&json);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bin);
    vec![
        ("mirrored-tangents.gltf", with.into_bytes()),
        ("mirrored.gltf", without.into_bytes()),
        ("mirrored-tangents.glb", glb),
    ]
}

/// Seeds of the `mikktspace` target (see `harness::mikktspace_soup`): a grid of quads whose
/// positions and UVs take the palette's values in the grid's order (the second is −0, beside +0,
/// so the first row and column of quads are degenerate: seeds of that path too), the same with UVs
/// folded (mirrored), and pseudo-random bytes.
fn mikktspace_seeds() -> Vec<(String, Vec<u8>)> {
    let mut values: Vec<u8> = (0..16u8).map(|k| k * 16 / 2).collect();
    values[1] = 0x80; // −0 beside +0
    let grid = |fold: bool| {
        let mut bytes = values.clone();
        for j in 0..3u8 {
            for i in 0..3u8 {
                let corner = |x: u8, y: u8| {
                    let u = if fold { x.min(4 - x) } else { x };
                    [x | y << 4, 3 | 7 << 4, u | y << 4]
                };
                for (x, y) in [
                    (i, j),
                    (i + 1, j),
                    (i + 1, j + 1),
                    (i, j),
                    (i + 1, j + 1),
                    (i, j + 1),
                ] {
                    bytes.extend(corner(x, y));
                }
            }
        }
        bytes
    };
    let mut seeds = vec![
        ("grid.bin".to_string(), grid(false)),
        ("grid-mirrored.bin".to_string(), grid(true)),
    ];
    let mut rng = harness::Rng::new(13);
    for size in [64usize, 400, 3000] {
        let bytes = (0..size).map(|_| rng.next_u64() as u8).collect();
        seeds.push((format!("random-{size}.bin"), bytes));
    }
    seeds
}
