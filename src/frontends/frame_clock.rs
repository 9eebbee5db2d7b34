//! The frame clock every front end's host keeps: each frame's time and the tutorial's
//! once-a-second "ms/frame" figure ([`FrameTimer`], `lastTime` and `nbFrames` in `tutorial13.cpp`).

use std::time::Duration;

use crate::clock::Instant;

/// A front end's clock: the time since it started and since the last frame (what the camera moves
/// by), and the tutorial's once-a-second "ms/frame" figure ([`FrameTimer`]).
pub struct FrameClock {
    started: Instant,
    last_time: Instant,
    timer: FrameTimer,
    ms_per_frame: Option<f64>,
}

/// What [`FrameClock::tick`] measured for a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tick {
    /// Seconds since the last frame.
    pub delta_time: f32,
    /// Seconds since the clock started.
    pub time: f32,
    /// A new "ms/frame" figure, once a second.
    pub ms_per_frame: Option<f64>,
}

impl FrameClock {
    pub fn new() -> Self {
        let now = Instant::now();
        FrameClock {
            started: now,
            last_time: now,
            timer: FrameTimer::new(),
            ms_per_frame: None,
        }
    }

    /// A frame starts now.
    pub fn tick(&mut self) -> Tick {
        let now = Instant::now();
        let delta_time = (now - self.last_time).as_secs_f32();
        self.last_time = now;
        let ms_per_frame = self.timer.tick(now);
        if ms_per_frame.is_some() {
            self.ms_per_frame = ms_per_frame;
        }
        Tick {
            delta_time,
            time: (now - self.started).as_secs_f32(),
            ms_per_frame,
        }
    }

    /// Seconds since the clock started, now (the panel's clock: egui's animations and double
    /// clicks).
    pub fn seconds(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// The last "ms/frame" figure (`None` in the first second).
    pub fn ms_per_frame(&self) -> Option<f64> {
        self.ms_per_frame
    }
}

impl Default for FrameClock {
    fn default() -> Self {
        Self::new()
    }
}

/// The tutorial's once-a-second "ms/frame" figure, computed as the tutorial does: 1000 divided by
/// the frames counted since the last print, and the next second starts exactly one second after the
/// last (not when the print happened), so a slow frame does not shift every later figure.
pub struct FrameTimer {
    last_time: Instant,
    nb_frames: u32,
}

impl FrameTimer {
    pub fn new() -> Self {
        FrameTimer {
            last_time: Instant::now(),
            nb_frames: 0,
        }
    }

    /// Counts a frame; once a second or more has passed since `last_time`, returns ms/frame.
    pub fn tick(&mut self, now: Instant) -> Option<f64> {
        self.nb_frames += 1;
        if now.duration_since(self.last_time) < Duration::from_secs(1) {
            return None;
        }
        let ms = 1000.0 / f64::from(self.nb_frames);
        self.nb_frames = 0;
        self.last_time += Duration::from_secs(1);
        Some(ms)
    }
}

impl Default for FrameTimer {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if the figure is not the tutorial's 1000 / frames, or the next second does not start
    // exactly one second after the last one.
    #[test]
    fn frame_timer_counts_as_the_tutorial() {
        let mut timer = FrameTimer::new();
        let start = timer.last_time;
        let ms = |t: f64| start + Duration::from_secs_f64(t);
        assert_eq!(timer.tick(ms(0.3)), None);
        assert_eq!(timer.tick(ms(0.6)), None);
        assert_eq!(timer.tick(ms(0.9)), None);
        assert_eq!(timer.tick(ms(1.25)), Some(250.0)); // 4 frames in the first second
        assert_eq!(timer.last_time, ms(1.0));
        assert_eq!(timer.tick(ms(1.5)), None);
        assert_eq!(timer.tick(ms(2.0)), Some(500.0)); // 2 frames in the next
    }
}
