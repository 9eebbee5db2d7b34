//! The `heightmap` target: the `normalmap` tool's height maps.

use std::path::Path;

use tutorial13::normalmap::{normal_map, HeightMap, Kernel, NormalMapOptions};

use super::{rejected, Outcome};

/// The `heightmap` target's check (see [`Target::Heightmap`](super::Target::Heightmap)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    match HeightMap::from_bytes(input, path) {
        Err(e) => rejected(path, e),
        Ok(heights) => {
            let texels = heights.width as usize * heights.height as usize;
            if texels == 0 || heights.values.len() != texels {
                return Err(format!(
                    "height map loaded as {}x{} with {} values",
                    heights.width,
                    heights.height,
                    heights.values.len()
                ));
            }
            for kernel in [Kernel::Sobel, Kernel::Scharr, Kernel::Central] {
                let options = NormalMapOptions {
                    kernel,
                    strength: 50.0,
                    ..Default::default()
                };
                let normals = normal_map(&heights, options);
                if normals.len() != texels {
                    return Err(format!("{} normals for {texels} texels", normals.len()));
                }
                if let Some(t) = normals.iter().find(|t| t[2] < 128) {
                    return Err(format!(
                        "{kernel:?}: a normal facing into the surface: {t:?}"
                    ));
                }
            }
            Ok(Outcome::Loaded)
        }
    }
}
