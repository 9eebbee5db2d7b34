//! What the browser page's URL asks for: `index.html?scene=NAME&panel=off&frames=N&s3tc=off`. A pure
//! function of the query string, compiled natively too, so that its tests run with the others (the
//! page itself, `frontends::web`, is wasm32 only).
//!
//! - `scene=NAME`: the scene (the cylinder without it); an unknown name is `--scene`'s error.
//! - `panel=off` (or `on`): without the panel.
//! - `frames=N`: N frames with time frozen at 0, as `--frames N`, then stop; input still moves the
//!   camera, by [`FROZEN_STEP_S`] a frame.
//! - `s3tc=off` (or `on`): the page acts as a browser without `WEBGL_compressed_texture_s3tc`, so
//!   that the DXT textures are decoded on the CPU (the page's script hides the extension from the
//!   module before WebGL2 is asked for; the module checks it is hidden).
//!
//! - `tour=N` (or a step's name): the tutorial's tour at that step, its pane shown, as `--tour N`;
//!   the step's scene replaces `scene=`.
//!
//! Other keys (the tests' `click`, `key`, `drag`, `wheel`, `drop`) are the page's script's, and are
//! let through.

use crate::scenes::{self, SceneDescriptor};
use crate::tour::{Step, STEPS};

/// The seconds each frame of `frames=N` moves the camera by (the page's timer's period): time stays
/// at 0, but a drag turns the camera and a held arrow key moves it `speed × FROZEN_STEP_S` a frame,
/// so that the host predicts the frame a test's input gives.
pub const FROZEN_STEP_S: f32 = 0.016;

/// What the page's URL asks for (see the module's documentation).
#[derive(Debug, Clone, Copy)]
pub struct PageContract {
    pub scene: &'static SceneDescriptor,
    pub panel: bool,
    pub frames: Option<u32>,
    /// `false` with `s3tc=off`: the DXT textures must be decoded on the CPU.
    pub s3tc: bool,
    /// `tour=N`: the tour's step to start at (`scene` is its scene).
    pub tour: Option<&'static Step>,
}

impl Default for PageContract {
    fn default() -> Self {
        PageContract {
            scene: scenes::default_scene(),
            panel: true,
            frames: None,
            s3tc: true,
            tour: None,
        }
    }
}

impl PageContract {
    /// Reads the query string (`location.search`, with or without its `?`): an error names the
    /// pair and what it takes.
    pub fn parse(query: &str) -> Result<Self, String> {
        let mut contract = PageContract::default();
        let on_off = |key: &str, value: &str| match value {
            "on" => Ok(true),
            "off" => Ok(false),
            _ => Err(format!("{key}={value}: on or off")),
        };
        let query = query.strip_prefix('?').unwrap_or(query);
        for pair in query.split('&').filter(|p| !p.is_empty()) {
            let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
            match key {
                "scene" => {
                    contract.scene =
                        scenes::find(value).map_err(|e| format!("scene={value}: {e}"))?
                }
                "panel" => contract.panel = on_off(key, value)?,
                "s3tc" => contract.s3tc = on_off(key, value)?,
                "frames" => {
                    let frames = value.parse().ok().filter(|&n: &u32| n > 0);
                    contract.frames =
                        Some(frames.ok_or_else(|| {
                            format!("frames={value}: a number of frames, 1 or more")
                        })?);
                }
                "tour" => {
                    let step = crate::tour::find(value).map_err(|_| {
                        format!(
                            "tour={value}: a step's number from 1 to {} or its name, such as {}",
                            STEPS.len(),
                            STEPS[0].name
                        )
                    })?;
                    contract.tour = Some(step);
                }
                _ => {}
            }
        }
        if let Some(step) = contract.tour {
            contract.scene = step.state.descriptor().map_err(|e| e.to_string())?;
        }
        Ok(contract)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The contract's fields as text, for comparisons (a descriptor by its name).
    fn fields(query: &str) -> Result<(&'static str, bool, Option<u32>, bool), String> {
        PageContract::parse(query).map(|c| (c.scene.name, c.panel, c.frames, c.s3tc))
    }

    // Fails if a query the tests and links use is read otherwise than the module says.
    #[test]
    fn the_pages_queries_are_read_as_documented() {
        let default = scenes::default_scene().name;
        assert_eq!(fields(""), Ok((default, true, None, true)));
        assert_eq!(fields("?"), Ok((default, true, None, true)));
        assert_eq!(
            fields("?scene=wall&panel=off&frames=3"),
            Ok(("wall", false, Some(3), true))
        );
        assert_eq!(
            fields("scene=cube&panel=on&s3tc=off"),
            Ok(("cube", true, None, false))
        );
        // The tests' input is the page script's; a key without a value, too.
        assert_eq!(
            fields("?frames=9&click=12,40&key=ArrowUp&drop=a.obj,a.mtl&debug"),
            Ok((default, true, Some(9), true))
        );
        for scene in scenes::SCENES {
            let query = format!("?scene={}", scene.name);
            assert_eq!(fields(&query).map(|f| f.0), Ok(scene.name));
        }
        // A step by number or name, its scene taking the place of `scene=`.
        for (i, step) in STEPS.iter().enumerate() {
            for value in [(i + 1).to_string(), step.name.to_string()] {
                let c = PageContract::parse(&format!("?scene=wall&tour={value}")).unwrap();
                assert!(
                    c.tour.is_some_and(|t| std::ptr::eq(t, step)),
                    "tour={value}"
                );
                assert_eq!(c.scene.name, step.state.scene, "tour={value}");
            }
        }
        assert!(PageContract::parse("").unwrap().tour.is_none());
    }

    fn tour_error(value: &str) -> String {
        format!("tour={value}: a step's number from 1 to 18 or its name, such as normal-textures")
    }

    // Fails if a bad value is let through, or its message does not name the pair and what it
    // takes (the page shows it as its one line).
    #[test]
    fn bad_values_are_refused_with_a_message() {
        let scene = scenes::find("nonsense").unwrap_err();
        for (query, message) in [
            ("?scene=nonsense", format!("scene=nonsense: {scene}")),
            (
                "?scene=",
                format!("scene=: {}", scenes::find("").unwrap_err()),
            ),
            (
                "?frames=abc",
                "frames=abc: a number of frames, 1 or more".into(),
            ),
            (
                "?frames=0",
                "frames=0: a number of frames, 1 or more".into(),
            ),
            (
                "?frames=-1",
                "frames=-1: a number of frames, 1 or more".into(),
            ),
            ("?frames", "frames=: a number of frames, 1 or more".into()),
            (
                "?frames=99999999999",
                "frames=99999999999: a number of frames, 1 or more".into(),
            ),
            ("?panel=no", "panel=no: on or off".into()),
            ("?tour=0", tour_error("0")),
            ("?tour=19", tour_error("19")),
            ("?tour=", tour_error("")),
            ("?tour=Results", tour_error("Results")),
            ("?s3tc=false", "s3tc=false: on or off".into()),
            (
                "?scene=wall&frames=2x",
                "frames=2x: a number of frames, 1 or more".into(),
            ),
        ] {
            assert_eq!(fields(query), Err(message), "{query}");
        }
        assert!(scene.contains("unknown scene 'nonsense'"), "{scene}");
    }
}
