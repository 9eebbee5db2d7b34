//! A glTF material read as the tutorial's: its diffuse and normal maps' pictures (read now,
//! decoded when the maps are uploaded), the UV set they are laid with, and the notices of what
//! the tutorial's shaders sample otherwise.

use std::path::PathBuf;
use std::sync::Arc;

use super::primitive::view_bytes;
use super::Reader;
use crate::model::{MapSource, Material};

impl Reader<'_> {
    /// A glTF material's maps (`None`: the default material, white and flat).
    pub(super) fn material(
        &self,
        material: Option<gltf::Material>,
        buffers: &[Vec<u8>],
        notices: &mut Vec<String>,
    ) -> Result<Material, String> {
        let Some(material) = material else {
            return Ok(Material {
                name: "(default)".into(),
                diffuse: MapSource::Neutral,
                normal: MapSource::Neutral,
                specular: MapSource::Neutral,
            });
        };
        let name = material.name().map_or_else(
            || format!("material {}", material.index().unwrap_or(0)),
            str::to_string,
        );
        self.check_tex_coord(&material, &name, notices);
        let pbr = material.pbr_metallic_roughness();
        let diffuse = match pbr.base_color_texture() {
            Some(info) => {
                let named_by = format!("baseColorTexture of '{name}'");
                self.check_sampler(&info.texture(), &named_by, notices);
                self.image(info.texture(), buffers, named_by, None)?
            }
            None => {
                let [r, g, b, _] = pbr.base_color_factor();
                MapSource::Colour([r, g, b])
            }
        };
        let normal = match material.normal_texture() {
            Some(info) => {
                let named_by = format!("normalTexture of '{name}'");
                let scale = Some(info.scale()).filter(|&s| s != 1.0);
                self.check_sampler(&info.texture(), &named_by, notices);
                self.image(info.texture(), buffers, named_by, scale)?
            }
            None => MapSource::Neutral,
        };
        Ok(Material {
            name,
            diffuse,
            normal,
            specular: MapSource::Neutral,
        })
    }

    /// Says when a material's two maps name different UV sets: the tutorial's shaders have one.
    fn check_tex_coord(&self, material: &gltf::Material, name: &str, notices: &mut Vec<String>) {
        if let (Some(d), Some(n)) = map_uv_sets(material) {
            if d != n {
                notices.push(format!(
                    "{}: '{name}': baseColorTexture uses TEXCOORD_{d}, normalTexture \
                     TEXCOORD_{n}: both are read with TEXCOORD_{n}, the normal map's (the \
                     tutorial's shaders have one UV set)",
                    self.path.display()
                ));
            }
        }
    }

    /// Says when a texture's sampler asks for wrapping other than glTF's default, REPEAT: every
    /// map is sampled the tutorial's way (REPEAT, trilinear), which differs only where UVs leave
    /// 0..1. Filters are not said: they change no texel's place.
    fn check_sampler(&self, texture: &gltf::Texture, named_by: &str, notices: &mut Vec<String>) {
        use gltf::texture::WrappingMode;
        let sampler = texture.sampler();
        let asked: Vec<String> = [("S", sampler.wrap_s()), ("T", sampler.wrap_t())]
            .into_iter()
            .filter(|(_, mode)| *mode != WrappingMode::Repeat)
            .map(|(axis, mode)| format!("{mode:?} on {axis}"))
            .collect();
        if !asked.is_empty() {
            notices.push(format!(
                "{}: {named_by}'s sampler asks for {}: sampled with Repeat, the tutorial's \
                 wrapping, which differs only where its UVs leave 0..1",
                self.path.display(),
                asked.join(" and ")
            ));
        }
    }

    /// A texture's picture, read now (decoded when the maps are uploaded).
    fn image(
        &self,
        texture: gltf::Texture,
        buffers: &[Vec<u8>],
        named_by: String,
        bump_multiplier: Option<f32>,
    ) -> Result<MapSource, String> {
        let image = texture.source();
        let what = format!("image {}", image.index());
        let (bytes, name) = match image.source() {
            gltf::image::Source::View { view, .. } => {
                (view_bytes(&view, buffers, &what)?.to_vec(), None)
            }
            gltf::image::Source::Uri { uri, .. } => {
                let name = (!uri.starts_with("data:")).then(|| uri.to_string());
                (self.uri(uri, &what)?, name)
            }
        };
        let mut path = self.path.as_os_str().to_owned();
        match name {
            Some(name) => path = self.folder.join(name).into_os_string(),
            None => path.push(format!(" ({what})")),
        }
        Ok(MapSource::Bytes {
            bytes: Arc::from(bytes),
            path: PathBuf::from(path),
            named_by: format!("{named_by} in {}", self.path.display()),
            bump_multiplier,
        })
    }
}

/// The UV set a material's maps are laid with: its normal map's (the tangent frame follows it),
/// else its diffuse map's, else TEXCOORD_0 (glTF's default material has no map).
pub(super) fn uv_set(material: &gltf::Material) -> u32 {
    let (diffuse, normal) = map_uv_sets(material);
    normal.or(diffuse).unwrap_or(0)
}

/// The UV sets a material's diffuse (`baseColorTexture`) and normal maps name, where it has them.
fn map_uv_sets(material: &gltf::Material) -> (Option<u32>, Option<u32>) {
    let pbr = material.pbr_metallic_roughness();
    (
        pbr.base_color_texture().map(|info| info.tex_coord()),
        material.normal_texture().map(|info| info.tex_coord()),
    )
}
