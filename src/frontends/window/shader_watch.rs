//! Live shader editing in the window: a saved shader file is noticed ([`ShaderWatch`]) and the
//! scene's programs are read again.

use std::path::PathBuf;
use std::time::{Duration, Instant, SystemTime};

use crate::scenes::Scene;

/// Notices when a shader file a scene reads is saved, so that the window reloads it while it runs.
/// It polls the files' modification times and sizes (a few `stat` calls, four times a second) rather
/// than subscribing to file-system events: editors save by rewriting, renaming or replacing a file,
/// and all of them change what `stat` reports.
pub struct ShaderWatch {
    stamps: Vec<(PathBuf, Option<(SystemTime, u64)>)>,
    last_poll: Instant,
}

/// How often the files are looked at.
const SHADER_POLL: Duration = Duration::from_millis(250);

impl ShaderWatch {
    /// Starts from the files `scene` reads now.
    pub fn new(scene: &dyn Scene) -> Self {
        ShaderWatch {
            stamps: stamps(scene),
            last_poll: Instant::now(),
        }
    }

    /// Whether a file changed (or another file is now read in its place) since the last time this
    /// said so; looks at most every 250 ms.
    pub fn changed(&mut self, scene: &dyn Scene, now: Instant) -> bool {
        if now.duration_since(self.last_poll) < SHADER_POLL {
            return false;
        }
        self.last_poll = now;
        let stamps = stamps(scene);
        if stamps == self.stamps {
            return false;
        }
        self.stamps = stamps;
        true
    }
}

fn stamps(scene: &dyn Scene) -> Vec<(PathBuf, Option<(SystemTime, u64)>)> {
    let stamp = |path: &PathBuf| {
        let meta = std::fs::metadata(path).ok()?;
        Some((meta.modified().ok()?, meta.len()))
    };
    scene
        .shader_files()
        .into_iter()
        .map(|path| {
            let stamp = stamp(&path);
            (path, stamp)
        })
        .collect()
}
