//! The cylinder scene's own command-line arguments: its files (the model and its maps), which no
//! control holds. The flags of its switches, choices and sliders (`--debug-lines`, `--tangents`,
//! `--view`, `--compare`, …) are its table's: see controls.rs.

use std::path::PathBuf;

use crate::model::MapOverrides;
use crate::scenes::flags::SharedArgs;
use crate::scenes::options::SceneArgs;

#[derive(clap::Args, Debug, Clone)]
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

/// The cylinder's files, as the command line (or a dropped file) names them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CylinderFiles {
    /// `--model FILE`: a learner's model (OBJ or glTF) in place of the tutorial's cylinder.
    pub model: Option<PathBuf>,
    /// `--diffuse`, `--normal-map`, `--specular`, `--height`: maps over the model's or the tutorial's.
    pub maps: MapOverrides,
    /// Which code reads and indexes the mesh: the ports in src/common/ or their fast twins, chosen
    /// by size where `None` (no flag: a test's or a benchmark's choice, `MeshOptions::code`).
    pub code: Option<crate::mesh::Code>,
}

impl SceneArgs for CylinderArgs {
    type Options = CylinderFiles;

    fn options(&self, _: &SharedArgs) -> Result<CylinderFiles, String> {
        if let Some(s) = self.strength.filter(|s| !s.is_finite()) {
            return Err(format!("--strength {s}: must be a finite number"));
        }
        Ok(CylinderFiles {
            model: self.model.clone(),
            maps: MapOverrides {
                diffuse: self.diffuse.clone(),
                normal: self.normal_map.clone(),
                specular: self.specular.clone(),
                height: self.height.clone(),
                strength: self.strength,
            },
            code: None,
        })
    }
}
