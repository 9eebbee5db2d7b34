//! `tutorial13 bake HIGH LOW -o normal.png`: a detailed model's normals baked into a simple model's
//! UV layout, in the tangent frame that will draw it ([`crate::bake`]).

use std::path::PathBuf;

use super::{parse_size, Depth, SizeOf};
use crate::bake::{
    BakeFiles, BakeProgress, BakeSettings, BakeStats, BakedMap, Pairing, Space, NO_PER_PIXEL_BAKE,
};
use crate::clock::Instant;
use crate::combine::{texels16, texels8};
use crate::normalmap::{check_map_output, Green};
use crate::normalmap::{normal_map_file, normal_map_file16};
use crate::tangent_source::TangentSource;
use crate::{Error, Result};

/// Bake a normal map from a detailed model (HIGH) into a simple model's UV layout (LOW), in the
/// tangent frame that will draw LOW (docs/tools.md, "Baking")
#[derive(clap::Args, Debug, Clone)]
pub struct BakeOptions {
    /// The detailed model: OBJ or glTF, anything --model reads
    pub high: PathBuf,
    /// The simple model whose UV layout the map fills: OBJ or glTF
    pub low: PathBuf,
    /// Output: .png (8 or 16 bits) or .bmp (8 bits)
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Map size: N (square) or WxH, each 1 to 16384
    #[arg(long, value_name = "N|WxH", default_value = "1024", value_parser = |s: &str| parse_size(s, SizeOf::Texels))]
    pub size: (u32, u32),
    /// K × K rays per texel, averaged (1 to 16)
    #[arg(long, value_name = "K", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=16))]
    pub samples: u32,
    /// How far out along LOW's normal the rays start (the cage), in LOW's file units [default: 5 %
    /// of LOW's bounding-sphere radius]
    #[arg(long, value_name = "D", allow_negative_numbers = true)]
    pub extrusion: Option<f32>,
    /// How far a ray goes from the cage, in LOW's file units [default: 2 × the extrusion; with
    /// --cage, 0: no bound, as Blender's]
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub max_distance: Option<f32>,
    /// A cage: LOW with its corners moved out (the same faces in the same order), in place of
    /// --extrusion; each ray starts at the cage's point and goes toward LOW's (Blender's cage object)
    #[arg(long, value_name = "CAGE", conflicts_with = "extrusion")]
    pub cage: Option<PathBuf>,
    /// Pair LOW's parts with HIGH's by name (OBJ objects or groups, glTF nodes or meshes; the
    /// suffixes _low/_lp and _high/_hp left out, case ignored): a LOW part's rays meet only its
    /// HIGH part
    #[arg(long)]
    pub match_names: bool,
    /// Texels filled around each UV island's edge
    #[arg(long, value_name = "M", default_value_t = 16)]
    pub margin: u32,
    /// The tangent frame the map is for
    #[arg(long, value_name = "TANGENTS", value_parser = BakedFrame,
          default_value_t = TangentSource::MikkTSpace)]
    pub tangents: TangentSource,
    /// With --tangents tutorial: each vertex's T, B and N normalized, as the article's text does
    /// (the scene's --normalize-tbn)
    #[arg(long)]
    pub normalize_tbn: bool,
    /// Green channel up the picture (OpenGL, the tutorial) or down (DirectX)
    #[arg(long, value_enum, default_value_t = Green::Up)]
    pub green: Green,
    /// Bits per channel: 16 needs a .png
    #[arg(long, value_name = "BITS", value_enum, default_value_t = Depth::Eight)]
    pub depth: Depth,
    /// A model-space map (the model's own axes) instead of a tangent-space one
    #[arg(long, conflicts_with_all = ["tangents", "normalize_tbn", "green"])]
    pub object_space: bool,
}

/// The frames `bake --tangents` takes, in the order its help lists them, each with what it is: every
/// [`TangentSource`] but the per-pixel one, with the bake's own default (MikkTSpace, not the
/// tutorial's).
const BAKED_FRAMES: [(TangentSource, &str); 3] = [
    (
        TangentSource::MikkTSpace,
        "MikkTSpace, computed from LOW (glTF's and Blender's convention)",
    ),
    (
        TangentSource::File,
        "LOW's own TANGENTs (a glTF that has them; MikkTSpace's where a primitive has none)",
    ),
    (
        TangentSource::Tutorial,
        "The tutorial's computeTangentBasis + indexVBO_TBN (summed, as its shader takes them)",
    ),
];

/// `bake --tangents`' parser: a [`TangentSource`] of [`BAKED_FRAMES`] by its name; `derivative`
/// refused with why ([`NO_PER_PIXEL_BAKE`]), in clap's one line that names the flag.
#[derive(Clone)]
struct BakedFrame;

impl clap::builder::TypedValueParser for BakedFrame {
    type Value = TangentSource;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> std::result::Result<TangentSource, clap::Error> {
        // A closure's error is clap's "invalid value 'V' for '--tangents <TANGENTS>': why".
        let by_name = |name: &str| match clap::ValueEnum::from_str(name, false) {
            Ok(TangentSource::Derivative) => Err(NO_PER_PIXEL_BAKE.to_string()),
            Ok(frame) if BAKED_FRAMES.iter().any(|(baked, _)| *baked == frame) => Ok(frame),
            _ => Err(format!(
                "one of {}",
                BAKED_FRAMES
                    .map(|(frame, _)| crate::choices::name(&frame))
                    .join(", ")
            )),
        };
        by_name.parse_ref(cmd, arg, value)
    }

    fn possible_values(
        &self,
    ) -> Option<Box<dyn Iterator<Item = clap::builder::PossibleValue> + '_>> {
        Some(Box::new(BAKED_FRAMES.iter().filter_map(|(frame, help)| {
            Some(clap::ValueEnum::to_possible_value(frame)?.help(*help))
        })))
    }
}

impl BakeOptions {
    /// `tutorial13 bake`'s arguments (those after `bake`), read as the program reads them: the
    /// browser page's bake worker gets its settings so. An error is clap's first line.
    pub fn from_args(args: &[String]) -> std::result::Result<BakeOptions, String> {
        #[derive(clap::Parser)]
        #[command(name = "bake")]
        struct Bake {
            #[command(flatten)]
            options: BakeOptions,
        }
        let args = std::iter::once("bake").chain(args.iter().map(String::as_str));
        match <Bake as clap::Parser>::try_parse_from(args) {
            Ok(bake) => Ok(bake.options),
            Err(e) => {
                let text = e.to_string();
                let line = text.lines().next().unwrap_or_default();
                Err(line.trim_start_matches("error: ").to_string())
            }
        }
    }
}

/// Reads both models, bakes, writes the map and says what happened.
pub fn bake(options: &BakeOptions) -> Result<()> {
    let start = Instant::now();
    check_map_output("-o", &options.output, options.depth.sixteen_bit())?;
    let (settings, files, map) = bake_map(options, None)?;
    let clock = Instant::now();
    crate::files::write_bytes_atomically(&options.output, &encode(options, &map)?)?;
    log::info!("bake: written in {:.2} s", clock.elapsed().as_secs_f64());
    report(options, &settings, &files, &map);
    log::info!("bake: {:.2} s in all", start.elapsed().as_secs_f64());
    Ok(())
}

/// Both models read (through [`crate::files::read`], which the browser page fills) and baked as
/// `options` say, `progress` told how far it is: everything but writing the map (the page's bake
/// worker runs this, web/src/bake.rs).
pub fn bake_map(
    options: &BakeOptions,
    progress: Option<BakeProgress>,
) -> Result<(BakeSettings, BakeFiles, BakedMap)> {
    if options.normalize_tbn && options.tangents != TangentSource::Tutorial {
        return Err(Error::Argument(
            "--normalize-tbn: only with --tangents tutorial (the other frames are unit already)"
                .into(),
        ));
    }
    let mut settings = BakeSettings {
        width: options.size.0,
        height: options.size.1,
        samples: options.samples,
        margin: options.margin,
        tangents: options.tangents,
        normalize_tbn: options.normalize_tbn,
        space: if options.object_space {
            Space::Object
        } else {
            Space::Tangent
        },
        ..BakeSettings::default()
    };
    if let Some(progress) = progress {
        progress("reading the models", 0.0);
    }
    let mut files = BakeFiles::load(&options.high, &options.low, &settings)?;
    if let Some(cage) = &options.cage {
        files.load_cage(cage)?;
    }
    if options.match_names {
        report_pairs(files.match_names()?);
    }
    let radius = files.low.placement.radius;
    if options.cage.is_none() {
        settings.extrusion = distance("--extrusion", options.extrusion, 0.05 * radius)?;
    }
    let max_distance_default = match options.cage {
        // No bound, as Blender's maximum ray distance 0 with a cage object.
        Some(_) => 0.0,
        // An extrusion near f32's largest keeps a finite default (its rays are bounded anyway).
        None => (2.0 * settings.extrusion).min(f32::MAX),
    };
    settings.max_distance = distance("--max-distance", options.max_distance, max_distance_default)?;
    if settings.max_distance <= 0.0 && options.cage.is_none() {
        return Err(Error::Argument(
            "--max-distance: must be more than 0 (the rays go nowhere)".into(),
        ));
    }
    let map = files.bake_with(&settings, progress)?;
    Ok((settings, files, map))
}

/// A distance beyond LOW's bounding radius (in LOW's file units), in one line with the numbers and
/// what to change; `None` for distances within it. The bake still runs, and no faster or slower:
/// rays go no farther than the models are wide ([`crate::bake::Reach`]). Only a `--max-distance`
/// given is said: its default follows the extrusion, whose own line says what to change. The page
/// shows it too.
pub fn scale_warning(
    options: &BakeOptions,
    settings: &BakeSettings,
    radius: f32,
) -> Option<String> {
    if settings.extrusion > radius {
        Some(format!(
            "warning: --extrusion {} is beyond LOW's bounding radius {}: the rays start outside \
             the whole model and meet HIGH's outermost surface, not the detail under each texel; \
             use a few percent of the radius (the default, 5 %, is {})",
            significant(settings.extrusion),
            significant(radius),
            significant(0.05 * radius)
        ))
    } else if options.max_distance.is_some() && settings.max_distance > radius {
        Some(format!(
            "warning: --max-distance {} is beyond LOW's bounding radius {}: a ray that misses \
             HIGH beside LOW goes on through the model and can meet its far side; use about twice \
             the extrusion (the default, {})",
            significant(settings.max_distance),
            significant(radius),
            significant(2.0 * settings.extrusion)
        ))
    } else {
        None
    }
}

/// `value` or `default`, which must be a finite distance of 0 or more.
fn distance(flag: &str, value: Option<f32>, default: f32) -> Result<f32> {
    let d = value.unwrap_or(default);
    if !(d.is_finite() && d >= 0.0) {
        return Err(Error::Argument(format!(
            "{flag} {d}: must be a finite distance of 0 or more"
        )));
    }
    Ok(d)
}

/// The map as the file `--output` names holds it (PNG or BMP by its extension): 8- or 16-bit
/// texels, green flipped for `--green down` (tangent space only).
pub fn encode(options: &BakeOptions, map: &BakedMap) -> Result<Vec<u8>> {
    // A model-space map has no green convention: its y is the model's.
    let green = match options.object_space {
        true => Green::Up,
        false => options.green,
    };
    let (w, h) = (map.width, map.height);
    if options.depth.sixteen_bit() {
        normal_map_file16(&options.output, &texels16(&map.normals, green), w, h)
    } else {
        normal_map_file(&options.output, &texels8(&map.normals, green), w, h)
    }
}

/// "1 ray", "2 rays".
fn rays(n: usize) -> String {
    format!("{n} ray{}", if n == 1 { "" } else { "s" })
}

/// `x` to four significant digits (a default distance is a fraction of the model's radius, whose
/// last digits say nothing).
fn significant(x: f32) -> String {
    if x == 0.0 || !x.is_finite() {
        return x.to_string();
    }
    if x.abs() >= 1e6 {
        // A distance far out of scale (`--extrusion 1e30`) in the form it was likely typed.
        let text = format!("{x:.3e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let decimals = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.decimals$}");
    match text.contains('.') {
        true => text.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => text,
    }
}

/// A few lines on stdout: the map, what it covers, a distance out of scale, the rays that missed and
/// what to change. A line that starts `warning: ` names a setting that spoils the map.
fn report(options: &BakeOptions, settings: &BakeSettings, files: &BakeFiles, map: &BakedMap) {
    let stats = &map.stats;
    let frame = frame_name(settings);
    println!(
        "wrote {} ({}x{}, {} bits) from {} ({} triangles) onto {} ({} triangles), for {frame}",
        options.output.display(),
        map.width,
        map.height,
        options.depth.bits(),
        options.high.display(),
        files.high_soup.triangle_count(),
        options.low.display(),
        files.low.soup.triangle_count(),
    );
    println!("{}", coverage(settings, map));
    if let Some(line) = scale_warning(options, settings, files.low.placement.radius) {
        println!("{line}");
    }
    println!("{}", misses(options, settings, stats, files.scale));
    report_flaws(settings, stats);
}

/// "covered N of M texels ...": the report's line that the page shows too.
pub fn coverage(settings: &BakeSettings, map: &BakedMap) -> String {
    let stats = &map.stats;
    let texels = map.states.len();
    format!(
        "covered {} of {texels} texels ({:.1} %) with {} rays ({}x{} per texel); the margin filled {} more",
        stats.covered,
        100.0 * stats.covered as f64 / texels as f64,
        stats.rays,
        settings.samples,
        settings.samples,
        stats.margin,
    )
}

/// The parts paired by name, one line each, and a notice for each part without a partner.
fn report_pairs(pairing: &Pairing) {
    let names = |names: &[String]| -> String {
        let quoted: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
        quoted.join(", ")
    };
    for pair in &pairing.pairs {
        println!(
            "paired LOW's {} ({} triangles) with HIGH's {} ({} triangles)",
            names(&pair.low.names),
            pair.low.triangles,
            names(&pair.high.names),
            pair.high.triangles
        );
    }
    let unnamed = |name: &str| match name {
        "" => {
            "the unnamed part (faces before any o or g, a node and mesh without a name)".to_string()
        }
        name => format!("'{name}'"),
    };
    for (name, triangles) in &pairing.unpaired_low {
        log::warn!(
            "--match-names: LOW's {} ({triangles} triangles) pairs with no part of HIGH: its \
             texels get the flat normal",
            unnamed(name)
        );
    }
    for (name, triangles) in &pairing.unpaired_high {
        log::warn!(
            "--match-names: HIGH's {} ({triangles} triangles) pairs with no part of LOW: no ray \
             meets it",
            unnamed(name)
        );
    }
}

/// The frame the map is baked for, in words.
fn frame_name(settings: &BakeSettings) -> String {
    match (settings.space, settings.tangents, settings.normalize_tbn) {
        (Space::Object, ..) => "object space (the model's axes)".to_string(),
        (_, TangentSource::MikkTSpace, _) => "MikkTSpace's frame (glTF's, Blender's)".to_string(),
        (_, TangentSource::File, _) => "the file's own tangents".to_string(),
        (_, TangentSource::Tutorial, false) => {
            "the tutorial's frame (summed, as its shader takes it)".to_string()
        }
        (_, TangentSource::Tutorial, true) => {
            "the tutorial's frame, normalized (--normalize-tbn)".to_string()
        }
        (_, TangentSource::Derivative, _) => unreachable!("BakeFiles::load refuses it"),
    }
}

/// Above this share of the rays missing HIGH the line is a warning: that much of the map is flat.
const MISSED_WARNING: f64 = 0.02;

/// The rays that met nothing, and what to change (to how much, from where their HIGH was found);
/// or that every ray met HIGH (a line the page shows too). `scale`: placed units per LOW file unit.
pub fn misses(
    options: &BakeOptions,
    settings: &BakeSettings,
    stats: &BakeStats,
    scale: f32,
) -> String {
    if stats.missed == 0 {
        return "every ray met HIGH".into();
    }
    let mut advice = Vec::new();
    if stats.missed_outside > 0 {
        let by = stats.outside_by / scale;
        let change = match options.cage {
            Some(_) => "move the cage out there".to_string(),
            None => format!(
                "raise --extrusion to {} or more",
                significant(settings.extrusion + by)
            ),
        };
        advice.push(format!(
            "for {} HIGH lies outside the cage, up to {} beyond it: {change}",
            stats.missed_outside,
            significant(by),
        ));
    }
    if stats.missed_beyond > 0 {
        // Measured from the cage, as --max-distance is.
        advice.push(format!(
            "for {} HIGH lies farther in: raise --max-distance to {} or more",
            stats.missed_beyond,
            significant(stats.beyond_by / scale)
        ));
    }
    if advice.is_empty() {
        advice.push(
            "HIGH is on neither side of LOW there within LOW's bounding radius (a hole, or LOW \
             reaches past it)"
                .into(),
        );
    }
    let d = significant(settings.max_distance);
    let within = match &options.cage {
        Some(cage) if settings.max_distance == 0.0 => format!("from the cage ({})", cage.display()),
        Some(cage) => format!("within --max-distance {d} of the cage ({})", cage.display()),
        None => format!(
            "within --max-distance {d} of the cage (--extrusion {})",
            significant(settings.extrusion)
        ),
    };
    let share = stats.missed as f64 / stats.rays.max(1) as f64;
    let line = format!(
        "{} ({:.2} %) met nothing {within} and wrote the flat normal; {}",
        rays(stats.missed),
        100.0 * share,
        advice.join("; ")
    );
    let warning = if share > MISSED_WARNING {
        "warning: "
    } else {
        ""
    };
    format!("{warning}{line}")
}

/// What no setting of the bake mends: overlapping UVs, triangles without UV area, frames without an
/// inverse or without right angles.
fn report_flaws(settings: &BakeSettings, stats: &BakeStats) {
    if stats.overlapping > 0 {
        println!(
            "{} texels are claimed by two or more triangles (mirrored or overlapping UV islands): \
             the later triangle in the file is kept",
            stats.overlapping
        );
    }
    if stats.flat_uv_triangles > 0 {
        println!(
            "{} of LOW's triangles have no area in UV space and cover nothing",
            stats.flat_uv_triangles
        );
    }
    if stats.singular > 0 {
        println!(
            "{} fell where LOW's frame has no inverse (T, B and N in one plane): flat normal",
            rays(stats.singular)
        );
    }
    if let Some(skew) = stats.skew {
        if skew.skewed > 0 {
            println!(
                "no map can be right for this frame at {:.1} % of the covered texels: there its T, \
                 B and N are not at right angles with equal lengths (stretch median {:.2}, max {:.2}), \
                 and the shader normalizes the light after the frame stretched it, so the light comes \
                 out up to that many times too bright or dim, whatever the map holds \
                 (docs/tangent-space-sync.md). {}",
                100.0 * skew.skewed as f64 / stats.covered.max(1) as f64,
                skew.median,
                skew.max,
                if settings.normalize_tbn {
                    "--tangents mikktspace has right angles everywhere"
                } else {
                    "--normalize-tbn (drawn with the scene's --normalize-tbn) or --tangents mikktspace"
                }
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails if a default distance prints its float noise, a large or tiny one loses digits, or
    /// one far out of scale prints thirty digits.
    #[test]
    fn distances_print_to_four_significant_digits() {
        assert_eq!(significant(0.050_000_05), "0.05");
        assert_eq!(significant(0.100_000_1), "0.1");
        assert_eq!(significant(1234.567), "1235");
        assert_eq!(significant(0.000_123_456), "0.0001235");
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(1e30), "1e30");
        assert_eq!(significant(1.234_567e7), "1.235e7");
        assert_eq!(rays(1), "1 ray");
        assert_eq!(rays(2), "2 rays");
    }

    /// Fails if the page's bake worker reads its arguments otherwise than the command line does
    /// (its map would be baked at other settings), or gives more than clap's first line, without
    /// its "error: ", for an error (the per-pixel frame's refusal with its reason, too).
    #[test]
    fn the_pages_arguments_are_read_as_the_command_line() {
        let args = |text: &str| text.split(' ').map(String::from).collect::<Vec<_>>();
        let options = BakeOptions::from_args(&args(
            "high/h.obj low/l.obj -o low/l_normal.png --size 512 --samples 2 --tangents tutorial \
             --extrusion 0.1",
        ))
        .expect("the page's arguments");
        assert_eq!(
            (
                options.high.to_str(),
                options.low.to_str(),
                options.output.to_str()
            ),
            (
                Some("high/h.obj"),
                Some("low/l.obj"),
                Some("low/l_normal.png")
            )
        );
        assert_eq!(
            (
                options.size,
                options.samples,
                options.tangents,
                options.margin
            ),
            ((512, 512), 2, TangentSource::Tutorial, 16)
        );
        assert_eq!((options.extrusion, options.max_distance), (Some(0.1), None));
        assert_eq!(
            BakeOptions::from_args(&args("h.obj l.obj -o x.png --size 0")).unwrap_err(),
            "invalid value '0' for '--size <N|WxH>': 0 texels: a side must be 1 to 16384"
        );
        assert_eq!(
            BakeOptions::from_args(&args("h.obj l.obj -o x.png --extrusion abc")).unwrap_err(),
            "invalid value 'abc' for '--extrusion <D>': invalid float literal"
        );
        // The page's bake worker shows this line for the per-pixel frame the page does not list.
        assert_eq!(
            BakeOptions::from_args(&args("h.obj l.obj -o x.png --tangents derivative"))
                .unwrap_err(),
            format!("invalid value 'derivative' for '--tangents <TANGENTS>': {NO_PER_PIXEL_BAKE}")
        );
    }
}
