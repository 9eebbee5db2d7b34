//! The cylinder scene's command-line arguments: its files (the model and its maps). The flags of
//! its switches, choices and sliders (`--debug-lines`, `--tangents`, `--view`, `--compare`, …) are
//! its table's: see controls.rs.

use crate::debug::views::{NormalMapConvention, ShaderSwitches};
use std::path::PathBuf;

use crate::mesh::MeshOptions;
use crate::model::MapOverrides;
use crate::normalmap::Green;
use crate::scenes::options::{SceneArgs, SharedArgs};
use crate::tangents::TangentSource;

use super::CylinderOptions;

#[derive(clap::Args, Debug, Clone)]
#[command(next_help_heading = "Scene cylinder")]
pub struct CylinderArgs {
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
            // --compare is the compare key's flag (controls.rs).
            compare: None,
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
