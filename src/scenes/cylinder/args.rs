//! The cylinder scene's command-line arguments: its files, and the comparison to start with. The
//! flags of its switches, choices and sliders (`--debug-lines`, `--tangents`, `--view`, …) are its
//! table's: see controls.rs.

use crate::debug::compare::{CompareMode, SPLIT_START};
use crate::debug::views::{NormalMapConvention, ShaderSwitches};
use std::path::PathBuf;

use crate::mesh::MeshOptions;
use crate::model::MapOverrides;
use crate::normalmap::Green;
use crate::scenes::options::{SceneArgs, SharedArgs};
use crate::tangents::TangentSource;

use super::{CompareOptions, CylinderOptions};

#[derive(clap::Args, Debug, Clone)]
#[command(next_help_heading = "Scene cylinder")]
pub struct CylinderArgs {
    /// Compare two tangent sources in one frame: A left of the split line, B right of it
    /// (e.g. tutorial,mikktspace) (key K; A and D move the split)
    #[arg(long, value_name = "A,B", value_parser = parse_pair)]
    pub compare: Option<[TangentSource; 2]>,

    /// With --compare: show the per-pixel difference as a heat map (its largest difference is
    /// printed and in the title) instead of the two sides
    #[arg(long, requires = "compare")]
    pub compare_difference: bool,

    /// Your own model instead of the tutorial's cylinder, scaled onto it: a glTF 2.0 file (.gltf,
    /// .glb) with its textures, or an OBJ with UVs and the maps its .mtl names (docs/model.md says
    /// which and how). Dropping one on the window loads it too
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,

    /// Diffuse map over the material's (or the tutorial's diffuse.DDS); a missing or unreadable
    /// file is an error
    #[arg(long, value_name = "FILE")]
    pub diffuse: Option<PathBuf>,

    /// Normal map over the material's (or the tutorial's normal.bmp), green up. The tutorial's own
    /// cylinder shows a map turned by 180° (see `normalmap --invert`); a model shows it as made
    #[arg(long, value_name = "FILE", conflicts_with = "height")]
    pub normal_map: Option<PathBuf>,

    /// Specular map over the material's (or the tutorial's specular.DDS)
    #[arg(long, value_name = "FILE")]
    pub specular: Option<PathBuf>,

    /// A grey-scale height map (white high) made into the normal map as `normalmap` does (on the
    /// tutorial's cylinder, turned for its frame so that white still looks raised)
    #[arg(long, value_name = "FILE")]
    pub height: Option<PathBuf>,

    /// With --height: texels of relief that black-to-white stands for [default: 8]
    #[arg(
        long,
        value_name = "S",
        requires = "height",
        allow_negative_numbers = true
    )]
    pub strength: Option<f32>,
}

impl SceneArgs for CylinderArgs {
    type Options = CylinderOptions;

    fn options(&self, shared: &SharedArgs) -> Result<CylinderOptions, String> {
        if let Some(s) = self.strength.filter(|s| !s.is_finite()) {
            return Err(format!("--strength {s}: must be a finite number"));
        }
        Ok(CylinderOptions {
            // The toggles' flags (--debug-lines, --no-gram-schmidt, …) are the table's
            // (controls.rs): they are set through it once the scene is built.
            switches: ShaderSwitches {
                convention: NormalMapConvention {
                    green_down: shared.green == Green::Down,
                    ..NormalMapConvention::default()
                },
                ..ShaderSwitches::default()
            },
            line_mode: None,
            // --tangents is the table's (key F); the scene reads it before it builds the mesh.
            tangents: default_tangents(self.model.as_deref()),
            compare: self.compare.map(|sources| CompareOptions {
                sources,
                mode: if self.compare_difference {
                    CompareMode::Difference
                } else {
                    CompareMode::Split
                },
                split: SPLIT_START,
            }),
            model: self.model.clone(),
            maps: MapOverrides {
                diffuse: self.diffuse.clone(),
                normal: self.normal_map.clone(),
                specular: self.specular.clone(),
                height: self.height.clone(),
                strength: self.strength,
            },
            light: shared.light,
            light_power: shared.light_power,
            normal_strength: None,
            line_length: None,
            mesh: MeshOptions::default(),
            debug_lines: false,
        })
    }
}

/// A glTF model's own tangents, as its specification says; the tutorial's otherwise.
pub fn default_tangents(model: Option<&std::path::Path>) -> TangentSource {
    match model.is_some_and(crate::model::Format::is_gltf) {
        true => TangentSource::File,
        false => TangentSource::Tutorial,
    }
}

fn parse_pair(s: &str) -> std::result::Result<[TangentSource; 2], String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}' is not A,B, e.g. tutorial,mikktspace"))?;
    let parse = |name: &str| <TangentSource as clap::ValueEnum>::from_str(name.trim(), false);
    Ok([parse(a)?, parse(b)?])
}
