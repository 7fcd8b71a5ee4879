//! One scene's predicted correspondences drawn over the two cameras' real
//! images side by side, as the paper's Figures 3 and 4: each object's mask
//! outlined, a line from each human-view object to the robot-view object
//! it was matched to (green where the ground truth agrees, red where
//! not), and objects without a partner in the other view crossed in white.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use vref_scene::{ScenePair, Side};

use crate::canvas::{self, Area, drawing};
use crate::match_picture::Outcome;
use crate::{RenderError, Size, font};

const RIGHT: RGBColor = RGBColor(0, 200, 90);
const WRONG: RGBColor = RGBColor(235, 30, 30);
/// Outline of an object the method left without a partner.
const UNMATCHED: RGBColor = RGBColor(255, 215, 0);
const LONE: RGBColor = WHITE;
const BAND: RGBColor = RGBColor(250, 250, 250);
const GAP: u32 = 16;
const TOP: u32 = 44;
const BOTTOM: u32 = 30;

/// One camera's image and its measured objects.
#[derive(Debug, Clone)]
pub struct ViewImage<'a> {
    /// RGB, row-major, `width x height`.
    pub rgb: &'a [u8],
    pub width: u32,
    pub height: u32,
    pub objects: Vec<ImageObject>,
}

/// One object as drawn: its track id, the pixel it is seen at and its
/// mask's outline pixels.
#[derive(Debug, Clone)]
pub struct ImageObject {
    pub id: u64,
    pub centre: [f64; 2],
    pub outline: Vec<(u32, u32)>,
}

/// The picture of one scene matched by one method over its images.
#[derive(Debug, Clone)]
pub struct ImageMatchPicture<'a> {
    pair: &'a ScenePair,
    predicted: &'a [(u64, u64)],
    method: &'a str,
    human: &'a ViewImage<'a>,
    robot: &'a ViewImage<'a>,
}

impl<'a> ImageMatchPicture<'a> {
    /// `predicted` holds (human id, robot id) pairs; every id must be an
    /// object of `pair` (objects of the images that the pair lacks are
    /// outlined only).
    pub fn new(
        pair: &'a ScenePair,
        predicted: &'a [(u64, u64)],
        method: &'a str,
        human: &'a ViewImage<'a>,
        robot: &'a ViewImage<'a>,
    ) -> Self {
        Self {
            pair,
            predicted,
            method,
            human,
            robot,
        }
    }

    fn size(&self) -> Size {
        Size::new(
            self.human.width + GAP + self.robot.width,
            TOP + self.human.height.max(self.robot.height) + BOTTOM,
        )
    }

    /// The picture as PNG bytes.
    pub fn render_png(&self) -> Result<Vec<u8>, RenderError> {
        let outcome = Outcome::new(self.pair, self.predicted)?;
        let size = self.size();
        let pixels = [BAND.0, BAND.1, BAND.2];
        let mut pixels = pixels.repeat(size.width as usize * size.height as usize);
        self.paste(&mut pixels, size, self.human, 0);
        self.paste(&mut pixels, size, self.robot, self.human.width + GAP);
        self.outlines(&mut pixels, size, &outcome);
        canvas::render_png_over(size, pixels, |area| self.draw(area, &outcome))
    }

    /// Writes the picture to `out` as PNG.
    pub fn save(&self, out: &Path) -> Result<(), RenderError> {
        canvas::write(out, &self.render_png()?)
    }

    fn paste(&self, pixels: &mut [u8], size: Size, view: &ViewImage<'_>, left: u32) {
        let row_bytes = view.width as usize * 3;
        for v in 0..view.height as usize {
            let from = &view.rgb[v * row_bytes..(v + 1) * row_bytes];
            let start = ((TOP as usize + v) * size.width as usize + left as usize) * 3;
            pixels[start..start + row_bytes].copy_from_slice(from);
        }
    }

    /// Outlines two pixels thick, coloured by what the method made of
    /// each object.
    fn outlines(&self, pixels: &mut [u8], size: Size, outcome: &Outcome) {
        let sides = [
            (self.human, Side::Human, 0),
            (self.robot, Side::Robot, self.human.width + GAP),
        ];
        for (view, side, left) in sides {
            for object in &view.objects {
                let colour = self.state(outcome, side, object.id).outline;
                for &(u, v) in &object.outline {
                    for (du, dv) in [(0, 0), (1, 0), (0, 1)] {
                        let (x, y) = (
                            left + (u + du).min(view.width - 1),
                            TOP + (v + dv).min(view.height - 1),
                        );
                        let i = (y as usize * size.width as usize + x as usize) * 3;
                        pixels[i..i + 3].copy_from_slice(&[colour.0, colour.1, colour.2]);
                    }
                }
            }
        }
    }

    /// How to draw object `id` of `side`.
    fn state(&self, outcome: &Outcome, side: Side, id: u64) -> State {
        let graph = match side {
            Side::Human => &self.pair.human,
            Side::Robot => &self.pair.robot,
        };
        let Some(k) = graph.index_of(id) else {
            return State {
                outline: LONE,
                lone: false,
            };
        };
        match side {
            Side::Human => State {
                outline: if outcome.human_to_robot[k].is_none() && outcome.right[k] {
                    UNMATCHED
                } else if outcome.right[k] {
                    RIGHT
                } else {
                    WRONG
                },
                lone: !outcome.human_has_partner[k],
            },
            Side::Robot => {
                let matched_by = outcome.human_to_robot.iter().position(|a| *a == Some(k));
                State {
                    outline: match matched_by {
                        Some(i) if outcome.right[i] => RIGHT,
                        Some(_) => WRONG,
                        None => UNMATCHED,
                    },
                    lone: !outcome.robot_has_partner[k],
                }
            }
        }
    }

    fn draw(&self, area: &Area<'_>, outcome: &Outcome) -> Result<(), RenderError> {
        let right_left = (self.human.width + GAP) as i32;
        let centre = |view: &ViewImage<'_>, left: i32, id: u64| {
            view.objects.iter().find(|o| o.id == id).map(|o| {
                (
                    left + o.centre[0].round() as i32,
                    TOP as i32 + o.centre[1].round() as i32,
                )
            })
        };
        // Right pairs first, so that the fewer wrong ones stay on top.
        for want_right in [true, false] {
            for (i, prediction) in outcome.human_to_robot.iter().enumerate() {
                let (Some(a), true) = (prediction, outcome.right[i] == want_right) else {
                    continue;
                };
                let h = self.pair.human.objects()[i].id;
                let r = self.pair.robot.objects()[*a].id;
                if let (Some(from), Some(to)) =
                    (centre(self.human, 0, h), centre(self.robot, right_left, r))
                {
                    let colour = if want_right { RIGHT } else { WRONG };
                    area.draw(&PathElement::new(vec![from, to], colour.stroke_width(2)))
                        .map_err(drawing)?;
                }
            }
        }
        for (view, side, left) in [
            (self.human, Side::Human, 0),
            (self.robot, Side::Robot, right_left),
        ] {
            for object in &view.objects {
                let Some(p) = centre(view, left, object.id) else {
                    continue;
                };
                let state = self.state(outcome, side, object.id);
                if state.lone {
                    for (a, b) in [((-6, -6), (6, 6)), ((-6, 6), (6, -6))] {
                        let line = vec![(p.0 + a.0, p.1 + a.1), (p.0 + b.0, p.1 + b.1)];
                        area.draw(&PathElement::new(line, LONE.stroke_width(3)))
                            .map_err(drawing)?;
                    }
                } else {
                    area.draw(&Circle::new(p, 4, state.outline.filled()))
                        .map_err(drawing)?;
                }
            }
        }
        self.texts(area, outcome)
    }

    fn texts(&self, area: &Area<'_>, outcome: &Outcome) -> Result<(), RenderError> {
        let n = outcome.right.len();
        let title = format!(
            "{}   ·   method {}   ·   accuracy {:.3} ({} of {} human-view objects right)",
            self.pair.name,
            self.method,
            outcome.accuracy,
            outcome.right.iter().filter(|&&r| r).count(),
            n
        );
        let text = |s: &str, x: i32, y: i32, size: f64, h: HPos| {
            let style = TextStyle::from((font::FAMILY, size).into_font())
                .color(&BLACK)
                .pos(Pos::new(h, VPos::Center));
            area.draw_text(s, &style, (x, y)).map_err(drawing)
        };
        text(&title, 8, 13, 16.0, HPos::Left)?;
        text("human view (AR headset)", 8, 33, 13.0, HPos::Left)?;
        let right_left = (self.human.width + GAP) as i32;
        text(
            "robot view (robot camera)",
            right_left + 8,
            33,
            13.0,
            HPos::Left,
        )?;
        let bottom = (self.size().height - BOTTOM / 2) as i32;
        text(
            "outline and line green: right pair · red: wrong pair · yellow: left without partner · white cross: no partner in the other view",
            8,
            bottom,
            12.0,
            HPos::Left,
        )
    }
}

struct State {
    outline: RGBColor,
    /// The ground truth gives it no partner.
    lone: bool,
}
