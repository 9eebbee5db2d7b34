//! `--bench-panel K`: what the panel costs the window, measured in the window. Frames are timed
//! from the start of one to the start of the next (what the window's ms/frame figure counts: the
//! frame, the panel, the swap), K with the panel shown and K with it hidden, in alternating runs of
//! [`RUN`] frames so that a machine that slows down for a while slows both alike.

use std::time::Instant;

use crate::statistics::min_median;

/// Frames in each run before the panel is shown or hidden again (about a third of a second).
pub const RUN: u32 = 50;

/// The frame times gathered so far.
pub struct PanelBench {
    /// Frames to time in each state.
    frames: u32,
    /// When the frame being drawn started, and whether it shows the panel.
    current: Option<(Instant, bool)>,
    /// Frames drawn since the panel was last shown or hidden.
    in_run: u32,
    shown: Vec<f64>,
    hidden: Vec<f64>,
}

/// What [`PanelBench::next_frame`] asks of the window.
#[derive(Debug, PartialEq, Eq)]
pub enum Next {
    /// Draw the next frame, with the panel shown or not.
    Draw { panel_shown: bool },
    /// Enough frames in both states: print [`PanelBench::report`] and close.
    Done,
}

impl PanelBench {
    pub fn new(frames: u32) -> Self {
        PanelBench {
            frames: frames.max(1),
            current: None,
            in_run: 0,
            shown: Vec::new(),
            hidden: Vec::new(),
        }
    }

    /// A frame starts at `now`: the one before it is timed, and the panel is shown or hidden for
    /// this one (`panel_shown` is how the window has it now).
    pub fn next_frame(&mut self, now: Instant, panel_shown: bool) -> Next {
        if let Some((start, shown)) = self.current {
            let ms = (now - start).as_secs_f64() * 1e3;
            let times = if shown {
                &mut self.shown
            } else {
                &mut self.hidden
            };
            if times.len() < self.frames as usize {
                times.push(ms);
            }
        }
        let full = |t: &Vec<f64>| t.len() >= self.frames as usize;
        if full(&self.shown) && full(&self.hidden) {
            return Next::Done;
        }
        let mut show = panel_shown;
        if self.in_run >= RUN || full(if show { &self.shown } else { &self.hidden }) {
            show = !show;
            self.in_run = 0;
        }
        self.in_run += 1;
        self.current = Some((now, show));
        Next::Draw { panel_shown: show }
    }

    /// "K frames each, in runs of 50: panel shown min … median … ms/frame; hidden min … median …
    /// ms/frame; shown/hidden R (medians)".
    pub fn report(&self) -> String {
        let (shown_min, shown_median) = min_median(&self.shown);
        let (hidden_min, hidden_median) = min_median(&self.hidden);
        format!(
            "{} frames each, in runs of {RUN}: panel shown min {shown_min:.3} median \
             {shown_median:.3} ms/frame; hidden min {hidden_min:.3} median {hidden_median:.3} \
             ms/frame; shown/hidden {:.3} (medians)",
            self.frames,
            shown_median / hidden_median
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    // Fails if the runs do not alternate every RUN frames, if a frame is counted in the state it
    // was not drawn in, or if the bench stops before both states have their frames.
    #[test]
    fn runs_alternate_and_each_frame_counts_where_it_was_drawn() {
        let mut bench = PanelBench::new(120);
        let mut now = Instant::now();
        let mut shown = true;
        let mut states = Vec::new();
        while let Next::Draw { panel_shown } = bench.next_frame(now, shown) {
            shown = panel_shown;
            states.push(shown);
            // A frame with the panel takes 12 ms, one without 10 ms.
            now += Duration::from_millis(if shown { 12 } else { 10 });
        }
        assert!(bench.shown.iter().all(|&ms| (ms - 12.0).abs() < 1e-9));
        assert!(bench.hidden.iter().all(|&ms| (ms - 10.0).abs() < 1e-9));
        assert_eq!((bench.shown.len(), bench.hidden.len()), (120, 120));
        let run = RUN as usize;
        assert!(states[..run].iter().all(|&s| s), "{states:?}");
        assert!(states[run..2 * run].iter().all(|&s| !s), "{states:?}");
        assert!(states[2 * run..3 * run].iter().all(|&s| s), "{states:?}");
        assert!(bench.report().ends_with("shown/hidden 1.200 (medians)"));
    }
}
