//! "Debugging with colors" and the tutorial's shader experiments, as switches of
//! `NormalMappingDebug.*`: the same lighting as the tutorial's shaders, with uniforms that pick a
//! colour view (a tangent-space vector instead of the lit colour) or an experiment. With every switch
//! at the tutorial's setting it draws the tutorial's frame bit for bit (a test checks it). The
//! program itself is the cylinder scene's (`scenes::cylinder::DebugProgram`).

/// The vector a colour view shows ("Debugging with colors"): 0 = the lit result.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum DebugVector {
    #[default]
    Lit = 0,
    /// `normalize(LightDirection_tangentspace)`.
    Light = 1,
    /// `normalize(EyeDirection_tangentspace)`.
    Eye = 2,
    /// The normal read from the normal map.
    TextureNormal = 3,
}

/// What the fragment shader outputs: the lit colour, or one tangent-space vector raw or as
/// (v + 1) / 2, all three components or one as grey.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ColorView {
    pub vector: DebugVector,
    /// (v + 1) / 2 instead of v (whose negative parts clamp to black).
    pub mapped: bool,
    /// `None`: RGB = xyz; `Some(0..=2)`: that component alone, as grey.
    pub component: Option<u8>,
}

impl ColorView {
    /// Every view the `V` key steps through, in order (the cylinder's table; `C` steps the
    /// component).
    pub const CYCLE: [(DebugVector, bool); 7] = [
        (DebugVector::Lit, false),
        (DebugVector::Light, false),
        (DebugVector::Light, true),
        (DebugVector::Eye, false),
        (DebugVector::Eye, true),
        (DebugVector::TextureNormal, false),
        (DebugVector::TextureNormal, true),
    ];

    /// This view showing `vector` (raw, or (v + 1) / 2 if `mapped`).
    pub fn with_vector(self, vector: DebugVector, mapped: bool) -> Self {
        ColorView {
            vector,
            mapped,
            ..self
        }
    }
}

impl std::fmt::Display for ColorView {
    /// The `--view` name: `lit`, `light`, `light01`, `eye`, `eye01`, `normal`, `normal01`, with
    /// `.x`, `.y` or `.z` for one component.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = match self.vector {
            DebugVector::Lit => return f.write_str("lit"),
            DebugVector::Light => "light",
            DebugVector::Eye => "eye",
            DebugVector::TextureNormal => "normal",
        };
        let mapped = if self.mapped { "01" } else { "" };
        let component = match self.component {
            None => "",
            Some(0) => ".x",
            Some(1) => ".y",
            Some(_) => ".z",
        };
        write!(f, "{name}{mapped}{component}")
    }
}

impl std::str::FromStr for ColorView {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let bad = || {
            format!(
                "unknown view '{s}': use lit, light, light01, eye, eye01, normal or normal01, \
                 optionally with .x, .y or .z"
            )
        };
        let (name, component) = match s.rsplit_once('.') {
            Some((name, "x")) => (name, Some(0)),
            Some((name, "y")) => (name, Some(1)),
            Some((name, "z")) => (name, Some(2)),
            Some(_) => return Err(bad()),
            None => (s, None),
        };
        let (base, mapped) = match name.strip_suffix("01") {
            Some(base) => (base, true),
            None => (name, false),
        };
        let vector = match base {
            "lit" if !mapped && component.is_none() => DebugVector::Lit,
            "light" => DebugVector::Light,
            "eye" => DebugVector::Eye,
            "normal" => DebugVector::TextureNormal,
            _ => return Err(bad()),
        };
        Ok(ColorView {
            vector,
            mapped,
            component,
        })
    }
}

/// How a normal map's texels are read (article 002's conventions). The default is the tutorial's:
/// green up, `2c − 1`, three channels.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NormalMapConvention {
    /// Green points down the picture (DirectX's convention): the shader negates y.
    pub green_down: bool,
    /// `c × 255/127 − 128/127` instead of `2c − 1`: the byte 128 is exactly 0 and 255 exactly 1, so
    /// a flat texel (128, 128, 255) is exactly (0, 0, 1) (with `2c − 1` it is (1/255, 1/255, 1)).
    pub exact_expansion: bool,
    /// Only red and green hold data; z is rebuilt as `sqrt(1 − x² − y²)`.
    pub two_channel: bool,
}

impl std::fmt::Display for NormalMapConvention {
    /// "green up, 2c-1, 3 channels".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let green = if self.green_down { "down" } else { "up" };
        let expansion = if self.exact_expansion {
            "c*255/127-128/127"
        } else {
            "2c-1"
        };
        let channels = if self.two_channel { 2 } else { 3 };
        write!(f, "green {green}, {expansion}, {channels} channels")
    }
}

/// The tutorial's shader-side experiments.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShaderSwitches {
    /// Normalize T, B, N in camera space before building the TBN matrix, as the article's text does
    /// (the repository's shader does not).
    pub normalize_tbn: bool,
    /// Specular colour from the specular texture (× 0.3); off: the constant vec3(0.3).
    pub specular_texture: bool,
    pub view: ColorView,
    /// How the normal map is read.
    pub convention: NormalMapConvention,
}

impl Default for ShaderSwitches {
    /// The tutorial's repository shader.
    fn default() -> Self {
        ShaderSwitches {
            normalize_tbn: false,
            specular_texture: true,
            view: ColorView::default(),
            convention: NormalMapConvention::default(),
        }
    }
}
