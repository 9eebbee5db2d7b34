//! One line on stderr for a load that takes a while: nothing for a quick one, "loading X ..." once it
//! has taken half a second, and the time it took when it ends.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::thread::JoinHandle;
use std::time::Duration;

use crate::clock::Instant;

/// How long a load runs before it is announced.
pub const ANNOUNCE_AFTER: Duration = Duration::from_millis(500);

/// Announces `what` if it is still running after [`ANNOUNCE_AFTER`]; dropping it ends it.
pub struct Progress {
    what: String,
    start: Instant,
    done: Option<mpsc::Sender<()>>,
    watcher: Option<JoinHandle<()>>,
    announced: Arc<AtomicBool>,
}

impl Progress {
    pub fn start(what: String) -> Self {
        let (done, finished) = mpsc::channel::<()>();
        let announced = Arc::new(AtomicBool::new(false));
        let (line, flag) = (what.clone(), announced.clone());
        // The browser has no threads to watch from (and no terminal to say it on).
        #[cfg(target_arch = "wasm32")]
        let watcher = {
            drop((finished, line, flag));
            None
        };
        #[cfg(not(target_arch = "wasm32"))]
        let watcher = Some(std::thread::spawn(move || {
            // A message or a hang-up (the load ended) before the time: nothing to say.
            if let Err(mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(ANNOUNCE_AFTER) {
                log::info!("{line} ...");
                flag.store(true, Ordering::SeqCst);
            }
        }));
        Progress {
            what,
            start: Instant::now(),
            done: Some(done),
            watcher,
            announced,
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        drop(self.done.take());
        if let Some(watcher) = self.watcher.take() {
            let _ = watcher.join();
        }
        if self.announced.load(Ordering::SeqCst) {
            let seconds = self.start.elapsed().as_secs_f64();
            log::info!("{}: done in {seconds:.2} s", self.what);
        }
    }
}
