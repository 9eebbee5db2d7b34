//! The tour's pane, which the panel lays out on the frame's right while the learner follows the
//! tutorial's tour ([`crate::tour`]): the step's number and section, its caption, then each excerpt
//! of its code (a Rust item or a shader's region, as the binary's own source has it) in a monospace,
//! scrollable and selectable view, and the lines of the C++ original it ports, named and linked.
//! Its excerpts are resolved once per step, not per frame; with the tour closed it is not laid out
//! at all.

use crate::tour::exercise::{for_step, ExerciseCheck, Verdict};
use crate::tour::{excerpt, Excerpt, Step, STEPS};

/// Width of the pane, in points: about 60 characters of code at egui's monospace size.
pub const TOUR_WIDTH: f32 = 440.0;

/// A step's excerpts, resolved when the pane first shows it.
pub struct TourExcerpts {
    index: usize,
    excerpts: Vec<(String, Result<Excerpt, excerpt::Missing>)>,
}

impl TourExcerpts {
    /// `index`'s excerpts: `cached` if it is that step's, else resolved now.
    pub fn of(index: usize, cached: Option<TourExcerpts>) -> Option<TourExcerpts> {
        let step = STEPS.get(index)?;
        match cached {
            Some(cached) if cached.index == index => Some(cached),
            _ => Some(TourExcerpts {
                index,
                excerpts: step.excerpts(),
            }),
        }
    }

    fn step(&self) -> &'static Step {
        &STEPS[self.index]
    }
}

/// What a click on the pane asks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TourClick {
    Close,
    Back,
    Next,
    /// At an exercise step: check the learner's work (F2).
    Check,
}

/// Lays the pane out on the right of the frame, with the answer of the exercise check at its step
/// (and its heat map's texture) if there is one; returns its rectangle (points), the buttons'
/// rectangles, and what was clicked.
pub fn show_tour(
    ui: &mut egui::Ui,
    excerpts: &TourExcerpts,
    answer: Option<&ExerciseCheck>,
    heat_map: Option<&egui::TextureHandle>,
) -> (egui::Rect, Vec<(TourClick, egui::Rect)>, Option<TourClick>) {
    let step = excerpts.step();
    let mut buttons = Vec::new();
    let mut clicked = None;
    let response = egui::Panel::right("tutorial13-tour")
        .exact_size(TOUR_WIDTH)
        .resizable(false)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                for (click, text) in [
                    (TourClick::Back, "PageUp: back"),
                    (TourClick::Next, "PageDown: next"),
                    (TourClick::Close, "close the tour"),
                ] {
                    let response = ui.button(text);
                    buttons.push((click, response.rect));
                    if response.clicked() {
                        clicked = Some(click);
                    }
                }
            });
            ui.heading(format!(
                "{}/{}  {}",
                excerpts.index + 1,
                STEPS.len(),
                step.section
            ));
            ui.add(egui::Label::new(step.caption).wrap());
            if for_step(step.name).is_some() {
                let response = ui.button("F2: check my exercise");
                buttons.push((TourClick::Check, response.rect));
                if response.clicked() {
                    clicked = Some(TourClick::Check);
                }
                show_answer(ui, answer, heat_map);
            }
            ui.separator();
            egui::ScrollArea::both()
                .auto_shrink([false, false])
                .show(ui, |ui| show_code(ui, step, &excerpts.excerpts));
        });
    (response.response.rect, buttons, clicked)
}

/// The check's answer: its line, coloured by the verdict, and where the learner's frame differs
/// from the reference, as the compare view's heat map.
fn show_answer(
    ui: &mut egui::Ui,
    answer: Option<&ExerciseCheck>,
    heat_map: Option<&egui::TextureHandle>,
) {
    let Some(answer) = answer else {
        return;
    };
    let colour = match answer.verdict {
        Some(Verdict::Matches) => egui::Color32::LIGHT_GREEN,
        Some(Verdict::Differs(_)) => egui::Color32::LIGHT_RED,
        Some(Verdict::Untouched) | None => egui::Color32::LIGHT_YELLOW,
    };
    ui.add(egui::Label::new(egui::RichText::new(&answer.line).color(colour)).wrap());
    if let Some(texture) = heat_map {
        ui.small("where your frame differs from the reference (the compare view's heat map)");
        ui.image((texture.id(), texture.size_vec2()));
    }
}

/// Each excerpt under its title (the Rust item or the shader's region, its file and lines), then
/// the C++ lines the step ports, linked.
fn show_code(
    ui: &mut egui::Ui,
    step: &Step,
    excerpts: &[(String, Result<Excerpt, excerpt::Missing>)],
) {
    for (asked, found) in excerpts {
        match found {
            Ok(excerpt) => {
                let (first, last) = excerpt.lines;
                ui.strong(asked);
                ui.small(format!("{}, lines {first}–{last}", excerpt.file));
                // A `&str` is a read-only buffer: selectable, never edited.
                let mut text = excerpt.text;
                ui.add(
                    egui::TextEdit::multiline(&mut text)
                        .code_editor()
                        .desired_rows(1)
                        .desired_width(f32::INFINITY)
                        .layouter(&mut highlighted),
                );
            }
            Err(missing) => {
                ui.colored_label(egui::Color32::LIGHT_RED, format!("missing: {missing}"));
            }
        }
        ui.add_space(6.0);
    }
    if !step.cpp.is_empty() {
        ui.separator();
        ui.strong("the C++ original (opengl-tutorial.org's)");
        for cpp in step.cpp {
            ui.hyperlink_to(cpp.label(), cpp.url());
            ui.small(cpp.what);
        }
    }
}

/// Light highlighting: comments in green, the code bright; lines are not wrapped (the view
/// scrolls sideways), so that the code reads as in the file.
fn highlighted(
    ui: &egui::Ui,
    text: &dyn egui::TextBuffer,
    _wrap_width: f32,
) -> std::sync::Arc<egui::Galley> {
    let font = egui::TextStyle::Monospace.resolve(ui.style());
    let code = egui::Color32::from_gray(225);
    let comment = egui::Color32::from_rgb(120, 170, 120);
    let mut job = egui::text::LayoutJob::default();
    for line in text.as_str().split_inclusive('\n') {
        let split = line.find("//").unwrap_or(line.len());
        let (before, after) = line.split_at(split);
        job.append(before, 0.0, egui::TextFormat::simple(font.clone(), code));
        job.append(after, 0.0, egui::TextFormat::simple(font.clone(), comment));
    }
    ui.fonts_mut(|fonts| fonts.layout_job(job))
}
