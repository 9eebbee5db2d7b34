//! The tutorial's two exercises, checked: the learner's frame against the reference frame (the
//! program's own answer), and against the frame nobody changed, so that a learner who did nothing
//! is told so rather than congratulated. The frames are rendered by the scene host
//! (`frontends::host`: F2 at an exercise step, and `tutorial13 --headless --check-exercise N`);
//! this compares them.

use std::sync::Arc;

use image::RgbaImage;

/// One of the tutorial's exercises.
#[derive(Debug)]
pub struct Exercise {
    pub number: u8,
    /// The name of its step in the tour (`tour::STEPS`), where F2 checks it.
    pub step: &'static str,
    /// What the learner is asked to do, and where.
    pub task: &'static str,
    /// The program's own answer, which draws the reference frame.
    pub reference: &'static str,
}

/// The two exercises, in the tutorial's order.
pub const EXERCISES: [Exercise; 2] = [
    Exercise {
        number: 1,
        step: "exercise-1",
        task: "normalize each corner's tangent and bitangent before they are summed: edit \
               index_vbo_tbn in src/common/vboindexer.rs, rebuild, and check again",
        reference: "the N switch (normalize before summing), built by the fast twin of the \
                    indexer, which an edit of the port leaves as it is",
    },
    Exercise {
        number: 2,
        step: "exercise-2",
        task: "make NormalMapping.fragmentshader's colour normalize(EyeDirection_tangentspace): \
               edit a copy of shaders/ and check again with --shaders DIR",
        reference: "the colour view \"eye\" (V), the same vector from the debugging shader",
    },
];

/// The exercise numbered `n`, or a line saying which there are.
pub fn exercise(n: u8) -> Result<&'static Exercise, String> {
    EXERCISES
        .iter()
        .find(|e| e.number == n)
        .ok_or_else(|| format!("--check-exercise {n}: the tutorial has exercises 1 and 2"))
}

/// The exercise checked at the tour's step named `step`, if it is an exercise's.
pub fn for_step(step: &str) -> Option<&'static Exercise> {
    EXERCISES.iter().find(|e| e.step == step)
}

/// How two frames differ, counted as the compare view's difference counts them: a pixel differs
/// when one of its red, green and blue bytes does (alpha is not shown).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameDifference {
    /// Pixels that differ.
    pub pixels: usize,
    /// The largest difference of one channel, in levels (0..255).
    pub max: u8,
    /// The smallest rectangle holding them: (left, top, right, bottom), inclusive, rows from the
    /// top; `None` when none differ.
    pub within: Option<(u32, u32, u32, u32)>,
}

impl FrameDifference {
    /// `a` against `b`, of the same size (frames of another size differ everywhere).
    pub fn between(a: &RgbaImage, b: &RgbaImage) -> FrameDifference {
        if a.dimensions() != b.dimensions() {
            let (w, h) = a.dimensions();
            return FrameDifference {
                pixels: (w * h) as usize,
                max: 255,
                within: (w > 0 && h > 0).then(|| (0, 0, w - 1, h - 1)),
            };
        }
        let mut difference = FrameDifference {
            pixels: 0,
            max: 0,
            within: None,
        };
        for (x, y, pa) in a.enumerate_pixels() {
            let pb = b.get_pixel(x, y);
            let d = crate::debug::compare::pixel_difference(pa, pb);
            if d > 0 {
                difference.pixels += 1;
                difference.max = difference.max.max(d);
                difference.within = Some(match difference.within {
                    None => (x, y, x, y),
                    Some((l, t, r, b)) => (l.min(x), t.min(y), r.max(x), b.max(y)),
                });
            }
        }
        difference
    }
}

/// What the check found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The learner's frame is the reference, pixel for pixel.
    Matches,
    /// The learner's frame is the one nobody changed: the exercise is not done yet.
    Untouched,
    /// It is neither: how it differs from the reference.
    Differs(FrameDifference),
}

impl Verdict {
    /// The learner's frame against the reference and the unchanged frame.
    pub fn of(learner: &RgbaImage, reference: &RgbaImage, unchanged: &RgbaImage) -> Verdict {
        let from_reference = FrameDifference::between(learner, reference);
        if from_reference.pixels == 0 {
            Verdict::Matches
        } else if FrameDifference::between(learner, unchanged).pixels == 0 {
            Verdict::Untouched
        } else {
            Verdict::Differs(from_reference)
        }
    }

    /// The one line the command prints for `exercise`.
    pub fn line(&self, exercise: &Exercise) -> String {
        let n = exercise.number;
        match self {
            Verdict::Matches => format!("exercise {n}: matches ({})", exercise.reference),
            Verdict::Untouched => format!(
                "exercise {n}: not done yet: your frame is the tutorial's own, unchanged; {}",
                exercise.task
            ),
            Verdict::Differs(d) => {
                let (l, t, r, b) = d.within.unwrap_or_default();
                format!(
                    "exercise {n}: {} pixels differ from the reference (by up to {} levels), \
                     within x {l}..={r}, y {t}..={b} from the top left",
                    d.pixels, d.max
                )
            }
        }
    }

    /// Whether the command exits 0.
    pub fn passed(&self) -> bool {
        *self == Verdict::Matches
    }
}

/// What a check found: the verdict, and where the learner's frame differs from the reference.
#[derive(Debug, Clone)]
pub struct ExerciseCheck {
    /// `None` where no check was made (the line says why: the page).
    pub verdict: Option<Verdict>,
    /// The one line the command prints and the pane shows ([`Verdict::line`]).
    pub line: String,
    /// Where the frames differ, as the compare view's heat map colours it
    /// ([`crate::debug::compare::heat_map`]), at most [`HEAT_MAP_WIDTH`] wide; `None` unless
    /// [`Verdict::Differs`].
    pub heat_map: Option<Arc<RgbaImage>>,
    /// Counts the checks, so that the panel tells one answer from the next.
    pub serial: u32,
}

impl PartialEq for ExerciseCheck {
    fn eq(&self, other: &Self) -> bool {
        self.serial == other.serial
    }
}

/// The widest heat map the pane shows, in pixels: its width, less its margins.
pub const HEAT_MAP_WIDTH: u32 = 420;

/// The line the page gives for F2: its shaders are built into it, and it has no `--shaders`.
pub const PAGE_CHECK_LINE: &str = "checking an exercise needs the native program: \
                                   tutorial13 --tour exercise-1 (or exercise-2), then F2";

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(pixels: &[(u32, u32, [u8; 4])]) -> RgbaImage {
        let mut image = RgbaImage::from_pixel(8, 6, image::Rgba([0, 0, 102, 255]));
        for &(x, y, p) in pixels {
            image.put_pixel(x, y, image::Rgba(p));
        }
        image
    }

    // Fails if the count, the largest difference or the rectangle are off for two changed pixels,
    // if alpha alone counts as a difference (the compare view does not show it), or if the verdict
    // congratulates a learner whose frame is the unchanged one.
    #[test]
    fn differences_are_counted_and_placed() {
        let unchanged = frame(&[]);
        let reference = frame(&[(1, 2, [10, 0, 102, 255]), (6, 4, [0, 3, 102, 255])]);
        let d = FrameDifference::between(&unchanged, &reference);
        assert_eq!(d.pixels, 2);
        assert_eq!(d.max, 10);
        assert_eq!(d.within, Some((1, 2, 6, 4)));
        let alpha_only = frame(&[(0, 0, [0, 0, 102, 0])]);
        assert_eq!(FrameDifference::between(&unchanged, &alpha_only).pixels, 0);

        assert_eq!(
            Verdict::of(&reference, &reference, &unchanged),
            Verdict::Matches
        );
        assert_eq!(
            Verdict::of(&unchanged, &reference, &unchanged),
            Verdict::Untouched
        );
        let wrong = frame(&[(1, 2, [10, 0, 102, 255])]);
        let Verdict::Differs(d) = Verdict::of(&wrong, &reference, &unchanged) else {
            panic!("a half-done exercise is neither a match nor untouched");
        };
        assert_eq!((d.pixels, d.max, d.within), (1, 3, Some((6, 4, 6, 4))));
        assert!(!Verdict::Untouched.passed() && Verdict::Matches.passed());
    }
}
