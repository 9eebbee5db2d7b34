//! `tutorial13 normalmap`: a height map (or one photo's guess at one) to a normal map file, or two
//! normal maps combined into one (`--combine`).

use std::path::{Path, PathBuf};

use super::Depth;
use crate::combine::{combine_maps, texels16, texels8, Method, NormalMap};
use crate::normalmap::{
    map_format, normal_map, write_normal_map, write_normal_map16, Green, HeightMap, Kernel,
    NormalMapOptions,
};
use crate::photometric::photo::{height_from_photo, Photo, DEFAULT_RADIUS};
use crate::{Error, Result};

/// Make a tangent-space normal map from a grey-scale height map (white high, black low; any size;
/// edges wrap so that tiling maps tile), guess one from a photo (--from-photo), or lay a detail
/// normal map over a base one (--combine)
#[derive(clap::Args, Debug, Clone)]
#[command(group(clap::ArgGroup::new("input").required(true).args(["height", "combine"])))]
pub struct NormalmapOptions {
    /// The height map: PNG, BMP, TGA or JPEG, 8 or 16 bits (colour is read as luma); with
    /// --from-photo, the photo
    pub height: Option<PathBuf>,
    /// Output: .bmp (24-bit, what the tutorial loads) or .png
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Texels of relief that black-to-white stands for (larger = bumpier; negative turns the
    /// relief inside out)
    #[arg(
        long,
        value_name = "S",
        default_value_t = 8.0,
        allow_negative_numbers = true
    )]
    pub strength: f32,
    /// Green channel up the picture (OpenGL, the tutorial) or down (DirectX)
    #[arg(long, value_enum, default_value_t = Green::Up)]
    pub green: Green,
    /// Store x and y only (blue 0); readers rebuild z = sqrt(1 - x² - y²)
    #[arg(long)]
    pub two_channel: bool,
    /// Derivative filter
    #[arg(long, value_enum, default_value_t = Kernel::Sobel)]
    pub kernel: Kernel,
    /// Turn the map by 180° (red and green negated): the tutorial's own cylinder (scene
    /// cylinder without --model) shows every map that way round, so white looks raised there
    /// only with this. Not for --model, the wall or other programs (docs/model.md: "Which way is up")
    #[arg(long)]
    pub invert: bool,
    /// Guess the relief from one photo instead, CrazyBump's way (a guess: see docs/tools.md)
    ///
    /// The photo's luminance (sRGB decoded to linear light) minus a wide blur of it (--radius)
    /// is taken as the height: brighter than its surroundings = higher. It reads brightness, not
    /// shape: a dark stain or joint becomes a dent, a light one a ridge; an engraved shape lit
    /// from the front comes out raised; a bump lit from one side is shifted and flattened.
    /// Several photos under known lights (`tutorial13 photometric`) measure the surface instead
    #[arg(long)]
    pub from_photo: bool,
    /// With --from-photo: brightness changes wider than about R texels are removed (the blur is
    /// three box blurs of 2R+1 texels, near a Gaussian of σ ≈ R)
    #[arg(long, value_name = "R", default_value_t = DEFAULT_RADIUS,
          requires = "from_photo", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub radius: u32,
    /// Lay the normal map DETAIL over the normal map BASE instead (output: BASE's size; the
    /// --green given is both inputs' and the output's)
    #[arg(long, num_args = 2, value_names = ["BASE", "DETAIL"],
          conflicts_with_all = ["height", "strength", "two_channel", "kernel", "invert", "from_photo",
                              "radius"])]
    pub combine: Option<Vec<PathBuf>>,
    /// With --combine: how (docs/tools.md compares them)
    #[arg(long, value_enum, default_value_t = Method::Rnm, conflicts_with = "height")]
    pub method: Method,
    /// With --combine: times DETAIL repeats across BASE, any positive number (sampled bilinearly,
    /// wrapping)
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1.0,
        conflicts_with = "height"
    )]
    pub detail_scale: f32,
    /// With --combine: bits per channel, 8 or 16 (PNG only)
    #[arg(long, value_name = "BITS", value_enum, default_value_t = Depth::Eight,
          conflicts_with = "height")]
    pub depth: Depth,
}

/// Reads the height map (or the photo), makes the normal map, writes it and prints its name and size.
pub fn normalmap(options: &NormalmapOptions) -> Result<()> {
    if let Some([base, detail]) = options.combine.as_deref() {
        return combine(options, base, detail);
    }
    let Some(height) = &options.height else {
        return Err(Error::Argument(
            "give a height map, or --combine BASE DETAIL".into(),
        ));
    };
    let strength = options.strength;
    if !strength.is_finite() {
        return Err(Error::Argument(format!(
            "--strength {strength}: must be a finite number"
        )));
    }
    let heights = match options.from_photo {
        true => height_from_photo(&Photo::load(height)?, options.radius),
        false => HeightMap::load(height)?,
    };
    let map = NormalMapOptions {
        // Both slopes negated: the same as the height turned inside out.
        strength: if options.invert { -strength } else { strength },
        kernel: options.kernel,
        green: options.green,
        two_channel: options.two_channel,
    };
    let texels = normal_map(&heights, map);
    write_normal_map(&options.output, &texels, heights.width, heights.height)?;
    println!(
        "wrote {} ({}x{})",
        options.output.display(),
        heights.width,
        heights.height
    );
    Ok(())
}

/// `--combine BASE DETAIL`: reads both maps, lays the detail over the base, writes the result at
/// the base's size. The output's name and the scale are checked before anything is read; nothing is
/// written unless everything succeeds.
fn combine(options: &NormalmapOptions, base: &Path, detail: &Path) -> Result<()> {
    let scale = options.detail_scale;
    if !(scale.is_finite() && scale > 0.0) {
        return Err(Error::Argument(format!(
            "--detail-scale {scale}: must be a positive number"
        )));
    }
    let sixteen_bit = options.depth.sixteen_bit();
    let output = &options.output;
    if map_format(output)? != image::ImageFormat::Png && sixteen_bit {
        return Err(Error::Write {
            path: output.clone(),
            reason: "16-bit normal maps are written as PNG only: name it .png".into(),
        });
    }
    let green = options.green;
    let base = NormalMap::load(base, green)?;
    let detail = NormalMap::load(detail, green)?;
    let normals = combine_maps(&base, &detail, options.method, f64::from(scale));
    let (width, height) = (base.width, base.height);
    match sixteen_bit {
        true => write_normal_map16(output, &texels16(&normals, green), width, height)?,
        false => write_normal_map(output, &texels8(&normals, green), width, height)?,
    }
    println!("wrote {} ({width}x{height})", output.display());
    Ok(())
}
