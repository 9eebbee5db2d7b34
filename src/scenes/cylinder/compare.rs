//! The compare view's state on the scene: two tangent sources, each drawn whole, side by side or
//! as a heat map of their difference ([`crate::debug::compare`] draws it).

use crate::debug::compare::{CompareMode, CompareView};
use crate::debug::views::ColorView;
use crate::gl::buffers::MeshBuffers;
use crate::tangent_source::TangentSource;
use crate::Result;

use super::Cylinder;

/// The compare key's value: off (`mode` `None`) or on in a mode, comparing `pair` where one is
/// named (`--compare A,B`), else the pair the key picks (`Cylinder::sources_to_compare`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Comparing {
    pub mode: Option<CompareMode>,
    pub pair: Option<[TangentSource; 2]>,
}

impl Comparing {
    /// Off, side by side, difference: what the key steps through, each with the pair it picks.
    pub(super) const KEYS: [Comparing; 3] = [
        Comparing::keyed(None),
        Comparing::keyed(Some(CompareMode::Split)),
        Comparing::keyed(Some(CompareMode::Difference)),
    ];

    /// The view in `mode` comparing `pair`, as `--compare A,B` (with `--compare-difference`).
    pub const fn pair(pair: [TangentSource; 2], mode: CompareMode) -> Self {
        Comparing {
            mode: Some(mode),
            pair: Some(pair),
        }
    }

    const fn keyed(mode: Option<CompareMode>) -> Self {
        Comparing { mode, pair: None }
    }
}

impl Cylinder {
    /// The compare view now: its mode and pair, or off.
    pub(super) fn comparing(&self) -> Comparing {
        Comparing {
            mode: self.comparison.as_ref().map(|_| self.compare_view.mode),
            pair: self.comparison.as_ref().map(|(sources, _)| *sources),
        }
    }

    /// Sets the compare view to `comparing`. A pair it names is compared in its mode, even one of
    /// unlike pictures (the learner named it; the table says why it misleads); otherwise as the
    /// key does ([`Cylinder::set_compare`]).
    pub(super) fn set_comparing(&mut self, comparing: Comparing) -> Result<()> {
        if let (Some(pair), Some(mode)) = (comparing.pair, comparing.mode) {
            self.compare_sources = Some(pair);
            self.compare_view.mode = mode;
            return self.start_comparison(pair);
        }
        self.set_compare(comparing.mode)
    }

    /// Shows `sources` in the compare view (each drawn whole, the first left of the split).
    pub fn start_comparison(&mut self, sources: [TangentSource; 2]) -> Result<()> {
        self.mesh.built.extend(sources);
        let upload = |source: TangentSource| -> Result<MeshBuffers> {
            MeshBuffers::new(&self.gl, &self.mesh.soup.mesh(source, self.mesh.options)?)
        };
        self.comparison = Some((sources, [upload(sources[0])?, upload(sources[1])?]));
        Ok(())
    }

    /// Back to one frame.
    pub fn stop_comparison(&mut self) {
        self.comparison = None;
    }

    /// The compare view's state, while it is on.
    pub fn compare_view(&self) -> Option<&CompareView> {
        self.comparison.as_ref().map(|_| &self.compare_view)
    }

    /// "compare A | B at 50 %" or "compare A − B: N pixels differ, max M levels", or nothing.
    pub(super) fn compare_status(&self) -> Option<String> {
        let (Some((sources, _)), view) = (&self.comparison, &self.compare_view) else {
            return None;
        };
        let [a, b] = sources;
        Some(match (view.mode, view.difference()) {
            (CompareMode::Split, _) => {
                format!("compare {a} | {b} at {:.0} %", view.split * 100.0)
            }
            (CompareMode::Difference, Some(d)) => format!(
                "compare {a} - {b}: {} pixels differ, max {} levels",
                d.pixels, d.max
            ),
            (CompareMode::Difference, None) => format!("compare {a} - {b}"),
        })
    }

    /// The compare view off (`None`), or on in `mode`, comparing `--compare`'s sources, else the
    /// current one and the next. A comparison of a colour view with the per-pixel frame, which
    /// draws none, is not started.
    pub(super) fn set_compare(&mut self, mode: Option<CompareMode>) -> Result<()> {
        let Some(mode) = mode else {
            self.stop_comparison();
            return Ok(());
        };
        if self.comparison.is_none() {
            if self.unlike_comparison().is_some() {
                return Ok(());
            }
            self.compare_view.mode = mode;
            self.start_comparison(self.sources_to_compare())?;
        }
        self.compare_view.mode = mode;
        Ok(())
    }

    /// The sources the compare key compares: those compared now, else `--compare`'s, else the
    /// current one and the next that key F would pick.
    fn sources_to_compare(&self) -> [TangentSource; 2] {
        let current = self.mesh.source;
        let compared = self.comparison.as_ref().map(|(sources, _)| *sources);
        compared.or(self.compare_sources).unwrap_or_else(|| {
            let sources = self.mesh.soup.tangent_sources();
            let i = sources.iter().position(|&s| s == current);
            [current, sources[i.map_or(0, |i| (i + 1) % sources.len())]]
        })
    }

    /// Why the compare view would not compare like with like: a colour view on, and a side drawn
    /// with the per-pixel frame, which draws the lit picture only.
    pub(super) fn unlike_comparison(&self) -> Option<&'static str> {
        let colour_view = self.switches.view != ColorView::default();
        let derivative = self
            .sources_to_compare()
            .contains(&TangentSource::Derivative);
        (colour_view && derivative).then_some(
            "a colour view is on (V) and a side is the per-pixel frame, which draws none: the two \
             sides would not show the same thing",
        )
    }

    /// Moves the compare view's split line by `step` of the width.
    pub(super) fn move_split(&mut self, step: f32) -> Result<()> {
        let view = &mut self.compare_view;
        view.split = (view.split + step).clamp(0.0, 1.0);
        Ok(())
    }
}
