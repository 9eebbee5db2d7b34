//! The `lights` target: the photometric tool's light-directions and light-intensities files.

use std::path::Path;

use glam::Vec3;

use tutorial13::photometric::{parse_intensities_file, parse_lights_file};

use super::{rejected, Outcome};

/// The `lights` target's check (see [`Target::Lights`](super::Target::Lights)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    let Ok(text) = std::str::from_utf8(input) else {
        return Ok(Outcome::Rejected("not UTF-8".into()));
    };
    let lights = parse_lights_file(text, path)
        .map(|lights| lights.iter().all(|l| l.is_finite() && *l != Vec3::ZERO));
    let intensities = parse_intensities_file(text, path)
        .map(|rgb| rgb.iter().flatten().all(|c| c.is_finite() && *c > 0.0));
    let mut outcome = Outcome::Loaded;
    for (what, parsed) in [("direction", lights), ("intensity", intensities)] {
        match parsed {
            Ok(true) => {}
            Ok(false) => return Err(format!("a {what} accepted that is not one")),
            Err(e) => outcome = rejected(path, e)?,
        }
    }
    Ok(outcome)
}
