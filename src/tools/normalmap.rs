//! `tutorial13 normalmap`: a height map (or one photo's guess at one) to a normal map file.

use std::path::PathBuf;

use crate::normalmap::{normal_map, write_normal_map, Green, HeightMap, Kernel, NormalMapOptions};
use crate::photo::{height_from_photo, Photo, DEFAULT_RADIUS};
use crate::{Error, Result};

/// Make a tangent-space normal map from a grey-scale height map (white high, black low; any size;
/// edges wrap so that tiling maps tile), or guess one from a photo (--from-photo)
#[derive(clap::Args, Debug, Clone)]
pub struct NormalmapOptions {
    /// The height map: PNG, BMP, TGA or JPEG, 8 or 16 bits (colour is read as luma); with
    /// --from-photo, the photo
    pub height: PathBuf,
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
}

/// Reads the height map (or the photo), makes the normal map, writes it and prints its name and size.
pub fn normalmap(options: &NormalmapOptions) -> Result<()> {
    let strength = options.strength;
    if !strength.is_finite() {
        return Err(Error::Argument(format!(
            "--strength {strength}: must be a finite number"
        )));
    }
    let heights = match options.from_photo {
        true => height_from_photo(&Photo::load(&options.height)?, options.radius),
        false => HeightMap::load(&options.height)?,
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
