//! Two camera images side by side with vref's answers drawn over them, for
//! frames without ground truth (`vref match`): each object's mask
//! outlined, and a line from each person-side object to its robot-side
//! partner coloured by the answer's status, so a person sees at a glance
//! what a robot would act on (green) and what it would ask about (orange).

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::canvas::{self, Area, drawing};
use crate::image_match::ViewImage;
use crate::{RenderError, Size, font};

const OK: RGBColor = RGBColor(0, 200, 90);
const AMBIGUOUS: RGBColor = RGBColor(255, 150, 0);
/// Outline of an object without a partner (no_match, or a robot object
/// nobody was matched to).
const ALONE: RGBColor = RGBColor(80, 160, 255);
const BAND: RGBColor = RGBColor(250, 250, 250);
const GAP: u32 = 16;
const TOP: u32 = 44;
const BOTTOM: u32 = 30;

/// An answer's status, as the live matcher gives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnswerStatus {
    Ok,
    Ambiguous,
    NoMatch,
}

/// One person-side object's answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Answer {
    pub human: u64,
    pub robot: Option<u64>,
    pub status: AnswerStatus,
}

/// The picture of one pair of frames and vref's answers.
#[derive(Debug, Clone)]
pub struct AnswerPicture<'a> {
    title: &'a str,
    human: &'a ViewImage<'a>,
    robot: &'a ViewImage<'a>,
    answers: &'a [Answer],
}

impl<'a> AnswerPicture<'a> {
    pub fn new(
        title: &'a str,
        human: &'a ViewImage<'a>,
        robot: &'a ViewImage<'a>,
        answers: &'a [Answer],
    ) -> Self {
        Self {
            title,
            human,
            robot,
            answers,
        }
    }

    fn size(&self) -> Size {
        Size::new(
            (self.human.width + GAP + self.robot.width).max(Size::MIN.width),
            (TOP + self.human.height.max(self.robot.height) + BOTTOM).max(Size::MIN.height),
        )
    }

    /// The picture as PNG bytes.
    pub fn render_png(&self) -> Result<Vec<u8>, RenderError> {
        // Too large a pair of images is refused by the canvas.
        let size = self.size();
        let mut pixels =
            [BAND.0, BAND.1, BAND.2].repeat(size.width as usize * size.height as usize);
        paste(&mut pixels, size, self.human, 0);
        paste(&mut pixels, size, self.robot, self.human.width + GAP);
        self.outlines(&mut pixels, size);
        canvas::render_png_over(size, pixels, |area| self.draw(area))
    }

    /// Writes the picture to `out` as PNG.
    pub fn save(&self, out: &Path) -> Result<(), RenderError> {
        canvas::write(out, &self.render_png()?)
    }

    fn human_colour(&self, id: u64) -> RGBColor {
        match self.answers.iter().find(|a| a.human == id) {
            Some(a) => status_colour(a.status),
            None => ALONE,
        }
    }

    fn robot_colour(&self, id: u64) -> RGBColor {
        // An object several answers name takes the surest of them.
        let mut colour = ALONE;
        for a in self.answers.iter().filter(|a| a.robot == Some(id)) {
            match a.status {
                AnswerStatus::Ok => return OK,
                AnswerStatus::Ambiguous => colour = AMBIGUOUS,
                AnswerStatus::NoMatch => {}
            }
        }
        colour
    }

    fn outlines(&self, pixels: &mut [u8], size: Size) {
        let right = self.human.width + GAP;
        for (view, left, human) in [(self.human, 0, true), (self.robot, right, false)] {
            for object in &view.objects {
                let c = if human {
                    self.human_colour(object.id)
                } else {
                    self.robot_colour(object.id)
                };
                for &(u, v) in &object.outline {
                    for (du, dv) in [(0, 0), (1, 0), (0, 1)] {
                        let x = left + (u + du).min(view.width.saturating_sub(1));
                        let y = TOP + (v + dv).min(view.height.saturating_sub(1));
                        let i = (y as usize * size.width as usize + x as usize) * 3;
                        if let Some(p) = pixels.get_mut(i..i + 3) {
                            p.copy_from_slice(&[c.0, c.1, c.2]);
                        }
                    }
                }
            }
        }
    }

    fn draw(&self, area: &Area<'_>) -> Result<(), RenderError> {
        let right = (self.human.width + GAP) as i32;
        let centre = |view: &ViewImage<'_>, left: i32, id: u64| {
            view.objects.iter().find(|o| o.id == id).map(|o| {
                (
                    left + o.centre[0].round() as i32,
                    TOP as i32 + o.centre[1].round() as i32,
                )
            })
        };
        // Ambiguous lines first, so that the ones a robot acts on stay on top.
        for status in [AnswerStatus::Ambiguous, AnswerStatus::Ok] {
            for a in self.answers.iter().filter(|a| a.status == status) {
                let Some(robot) = a.robot else { continue };
                if let (Some(from), Some(to)) = (
                    centre(self.human, 0, a.human),
                    centre(self.robot, right, robot),
                ) {
                    let style = status_colour(status).stroke_width(2);
                    area.draw(&PathElement::new(vec![from, to], style))
                        .map_err(drawing)?;
                }
            }
        }
        for (view, left, human) in [(self.human, 0, true), (self.robot, right, false)] {
            for object in &view.objects {
                let Some(p) = centre(view, left, object.id) else {
                    continue;
                };
                let c = if human {
                    self.human_colour(object.id)
                } else {
                    self.robot_colour(object.id)
                };
                area.draw(&Circle::new(p, 4, c.filled())).map_err(drawing)?;
            }
        }
        let text = |s: &str, x: i32, y: i32, size: f64| {
            let style = TextStyle::from((font::FAMILY, size).into_font())
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center));
            area.draw_text(s, &style, (x, y)).map_err(drawing)
        };
        text(self.title, 8, 13, 16.0)?;
        text("person's view", 8, 33, 13.0)?;
        text("robot's view", right + 8, 33, 13.0)?;
        let bottom = (self.size().height - BOTTOM / 2) as i32;
        text(
            "green: ok (a robot may act on it) · orange: ambiguous (ask which one) · blue: no partner",
            8,
            bottom,
            12.0,
        )
    }
}

fn status_colour(status: AnswerStatus) -> RGBColor {
    match status {
        AnswerStatus::Ok => OK,
        AnswerStatus::Ambiguous => AMBIGUOUS,
        AnswerStatus::NoMatch => ALONE,
    }
}

fn paste(pixels: &mut [u8], size: Size, view: &ViewImage<'_>, left: u32) {
    let row_bytes = view.width as usize * 3;
    for v in 0..view.height as usize {
        let (Some(from), start) = (
            view.rgb.get(v * row_bytes..(v + 1) * row_bytes),
            ((TOP as usize + v) * size.width as usize + left as usize) * 3,
        ) else {
            continue;
        };
        if let Some(to) = pixels.get_mut(start..start + row_bytes) {
            to.copy_from_slice(from);
        }
    }
}
