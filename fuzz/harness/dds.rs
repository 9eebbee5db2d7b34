//! The `dds` target: the DDS reader.

use std::path::Path;

use tutorial13::common::texture::{dxt_level_size, read_dds_bytes};

use super::{rejected, Outcome};

/// The `dds` target's check (see [`Target::Dds`](super::Target::Dds)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    match read_dds_bytes(input, path) {
        Err(e) => rejected(path, e),
        Ok(dds) => {
            let (mut w, mut h) = (dds.width, dds.height);
            if dds.levels.is_empty() || w == 0 || h == 0 {
                return Err(format!("DDS loaded with no level or size {w}x{h}"));
            }
            for (i, level) in dds.levels.iter().enumerate() {
                let size = dxt_level_size(dds.format, w, h);
                if (level.width, level.height, level.data.len()) != (w, h, size) {
                    return Err(format!(
                        "DDS level {i} is {}x{} with {} bytes, expected {w}x{h} with {size}",
                        level.width,
                        level.height,
                        level.data.len()
                    ));
                }
                w = (w / 2).max(1);
                h = (h / 2).max(1);
            }
            Ok(Outcome::Loaded)
        }
    }
}
