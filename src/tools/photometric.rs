//! `tutorial13 photometric`: photos under known lights to a normal map (and albedo) file.

use std::path::PathBuf;

use super::Depth;
use crate::normalmap::Green;
use crate::photometric::photo::Encoding;
use crate::photometric::{Job, Solver, DEFAULT_SHADOW};
use crate::Result;

/// Photometric stereo: a normal map (and albedo) from three or more photos under known lights
///
/// Photos of a surface from one camera position, each lit by one distant light from a known
/// direction (--light per photo, or --lights FILE) and of a known brightness (--intensity per
/// photo, or --intensities FILE; else all equally bright). Photos are read as sRGB (or --linear),
/// divided by their light's brightness and solved in linear light for Lambert's law. Per texel,
/// photos where it is near black (--shadow) or saturated (98 % of full scale) are left out; from
/// six photos on, the robust solver also leaves out the darkest tenth and the brightest quarter of
/// the rest (shadows, highlights) before least squares. Texels left with fewer than three photos, or with
/// lights within 5° of one plane, get the flat normal and are counted on stderr; outside --mask,
/// the flat normal and albedo 0. A lamp close to the surface and light bounced between its parts
/// break the model
#[derive(clap::Args, Debug, Clone)]
pub struct PhotometricOptions {
    /// The photos (PNG, JPEG, TGA or BMP, 8 or 16 bits), all the same size
    pub photos: Vec<PathBuf>,
    /// Direction towards the light of each photo, in the photos' order: x to the photo's right,
    /// y up it, z out of the surface towards the camera; any length (e.g. --light -1,0,1)
    #[arg(long = "light", value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub lights: Vec<String>,
    /// The lights' directions from a file instead: one `x y z` per photo and line, in the photos'
    /// order (blank lines and # comments allowed)
    #[arg(long = "lights", value_name = "FILE", conflicts_with = "lights")]
    pub lights_file: Option<PathBuf>,
    /// Brightness of each photo's light, in the photos' order: linear red, green, blue, or one
    /// value for all three, above zero (e.g. --intensity 0.9,1,1.1)
    #[arg(long = "intensity", value_name = "R,G,B", allow_hyphen_values = true)]
    pub intensities: Vec<String>,
    /// The lights' brightnesses from a file instead: one `r g b` per photo and line
    #[arg(
        long = "intensities",
        value_name = "FILE",
        conflicts_with = "intensities"
    )]
    pub intensities_file: Option<PathBuf>,
    /// Which texels to solve: an image of the photos' size, nonzero inside; outside, the flat
    /// normal and albedo 0
    #[arg(long, value_name = "FILE")]
    pub mask: Option<PathBuf>,
    /// lstsq: least squares over every photo kept (the textbook method); robust: leave out the
    /// darkest tenth and the brightest quarter of them per texel first. Default: robust from six
    /// photos on
    #[arg(long, value_enum)]
    pub solver: Option<Solver>,
    /// Bits per channel of the normal map: 8, or 16 (PNG only) so that quantisation does not
    /// bound its accuracy
    #[arg(long, value_name = "BITS", value_enum, default_value_t = Depth::Eight)]
    pub depth: Depth,
    /// Output normal map: .bmp (24-bit, what the tutorial loads) or .png
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Also write the albedo (the surface's colour without the lighting), .bmp or .png, encoded
    /// as the photos are
    #[arg(long, value_name = "FILE")]
    pub albedo: Option<PathBuf>,
    /// Green channel up the picture (OpenGL, the tutorial) or down (DirectX)
    #[arg(long, value_enum, default_value_t = Green::Up)]
    pub green: Green,
    /// The photos are linear already (a raw converter's linear output, a render), not sRGB
    #[arg(long)]
    pub linear: bool,
    /// Linear luminance below which a photo's texel counts as shadow and is left out
    #[arg(long, value_name = "L", default_value_t = DEFAULT_SHADOW)]
    pub shadow: f32,
}

/// Solves (see [`crate::photometric::run`]), warns on stderr of the texels left flat, and prints
/// what was written.
pub fn photometric(options: &PhotometricOptions) -> Result<()> {
    let recovered = crate::photometric::run(&Job {
        photos: &options.photos,
        lights: &options.lights,
        lights_file: options.lights_file.as_deref(),
        intensities: &options.intensities,
        intensities_file: options.intensities_file.as_deref(),
        mask: options.mask.as_deref(),
        output: &options.output,
        solver: options.solver,
        sixteen_bit: options.depth.sixteen_bit(),
        albedo: options.albedo.as_deref(),
        encoding: if options.linear {
            Encoding::Linear
        } else {
            Encoding::Srgb
        },
        green: options.green,
        shadow: options.shadow,
    })?;
    let (w, h, flat) = (recovered.width, recovered.height, recovered.unsolved);
    if flat > 0 {
        log::warn!(
            "{flat} of {} texels kept fewer than three photos (or photos whose lights are \
             nearly coplanar): flat normal there",
            w as usize * h as usize
        );
    }
    let albedo = options
        .albedo
        .iter()
        .map(|a| format!(" and {}", a.display()));
    println!(
        "wrote {}{} ({w}x{h})",
        options.output.display(),
        albedo.collect::<String>()
    );
    Ok(())
}
