//! `--tour` and `--check-exercise`, headless: a step of the tutorial's tour put in its state, and an
//! exercise's frame checked against the program's own answer.

use crate::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use crate::tour::exercise::{exercise, Verdict};
use crate::tour::Step;
use crate::{Error, Result};

/// What `--tour` asks for.
pub enum TourRequest {
    /// `--tour list`.
    List,
    /// `--tour N` or `--tour NAME`.
    Step(&'static Step),
}

/// `--tour`'s value read: `list`, or a step (a bad one is one line naming what the tour has).
pub fn tour_request(value: &str) -> Result<TourRequest> {
    match value {
        "list" => Ok(TourRequest::List),
        _ => crate::tour::find(value).map(TourRequest::Step),
    }
}

/// `--check-exercise N`: the scene host's check (the one F2 runs at the tour's exercise steps) of
/// the learner's frame with `options` (the command line's, its `--shaders` folder the learner's).
/// `Ok` with the line to print when the learner's frame is the reference; an
/// [`Error::Exercise`] with the line otherwise.
pub fn check_exercise(n: u8, options: &HeadlessOptions) -> Result<String> {
    let exercise = exercise(n).map_err(Error::Argument)?;
    if options.descriptor.name != "cylinder" {
        return Err(Error::Argument(format!(
            "--check-exercise {n}: the exercises are the tutorial's cylinder's (leave out --scene)"
        )));
    }
    let check = HeadlessRenderer::new(options)?
        .host
        .check_exercise(exercise)?;
    match check.verdict {
        Some(Verdict::Matches) => Ok(check.line),
        _ => Err(Error::Exercise(check.line)),
    }
}
