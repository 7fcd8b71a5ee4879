//! One scene's predicted correspondences: the two views side by side, a
//! line from each human-view object to the robot-view object it was
//! matched to, green where the ground truth agrees and red where not.

use std::collections::HashMap;
use std::path::Path;

use plotters::element::{DashedPathElement, Drawable, PointCollection};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use vref_match::score_scene;
use vref_scene::{SceneGraph, ScenePair, Side};

use crate::canvas::{self, Area, drawing};
use crate::projection::Fit;
use crate::{Projection, RenderError, Size, font};

const RIGHT: RGBColor = RGBColor(0, 150, 70);
const WRONG: RGBColor = RGBColor(215, 35, 35);
/// Objects that have a partner in the other view.
const PAIRED: RGBColor = RGBColor(40, 40, 48);
/// Objects that the ground truth gives no partner.
const LONE: RGBColor = RGBColor(160, 160, 160);
const EDGE: RGBColor = RGBColor(215, 215, 222);
const FRAME: RGBColor = RGBColor(200, 200, 205);
const LABEL: RGBColor = RGBColor(70, 70, 80);
const CAPTION: RGBColor = RGBColor(120, 120, 128);
/// Font sizes at 1200x600.
const TITLE_SIZE: f64 = 20.0;
const HEADER_SIZE: f64 = 15.0;
const CAPTION_SIZE: f64 = 12.0;
const LABEL_SIZE: f64 = 10.0;

/// The picture of one scene matched by one method.
#[derive(Debug, Clone)]
pub struct MatchPicture<'a> {
    pair: &'a ScenePair,
    predicted: &'a [(u64, u64)],
    method: &'a str,
    projection: Projection,
}

impl<'a> MatchPicture<'a> {
    /// `predicted` holds (human id, robot id) pairs, as
    /// `Solution::id_pairs` gives them; `method` names them in the title.
    pub fn new(pair: &'a ScenePair, predicted: &'a [(u64, u64)], method: &'a str) -> Self {
        Self {
            pair,
            predicted,
            method,
            projection: Projection::Auto,
        }
    }

    pub fn projection(mut self, projection: Projection) -> Self {
        self.projection = projection;
        self
    }

    /// The picture as PNG bytes.
    pub fn render_png(&self, size: Size) -> Result<Vec<u8>, RenderError> {
        let outcome = Outcome::new(self.pair, self.predicted)?;
        canvas::render_png(size, |area| self.draw(area, size, &outcome))
    }

    /// Writes the picture to `out` as PNG.
    pub fn save(&self, out: &Path, size: Size) -> Result<(), RenderError> {
        canvas::write(out, &self.render_png(size)?)
    }

    fn draw(&self, area: &Area<'_>, size: Size, outcome: &Outcome) -> Result<(), RenderError> {
        let pen = Pen::new(area, size);
        let pair = self.pair;
        let projection = self.projection.resolve(&[&pair.human, &pair.robot]);
        let (w, h) = (size.width as i32, size.height as i32);
        let margin = pen.px(16.0);
        let gap = pen.px(56.0);
        let top = pen.px(50.0);
        let bottom = h - pen.px(40.0);

        let human_panel = (margin, top, (w - gap) / 2, bottom);
        let robot_panel = ((w + gap) / 2, top, w - margin, bottom);
        let human = Panel::new(&pen, &pair.human, projection, human_panel)?;
        let robot = Panel::new(&pen, &pair.robot, projection, robot_panel)?;

        self.title(&pen, outcome)?;
        human.frame(&pen, "human view (AR headset)", projection)?;
        robot.frame(&pen, "robot view (robot camera)", projection)?;
        human.edges(&pen)?;
        robot.edges(&pen)?;
        // Right matches first, so that the fewer wrong ones stay on top.
        for want_right in [true, false] {
            for (i, prediction) in outcome.human_to_robot.iter().enumerate() {
                if let Some(a) = *prediction
                    && outcome.right[i] == want_right
                {
                    pen.correspondence(human.points[i], robot.points[a], want_right)?;
                }
            }
        }
        let human_state = (0..pair.human.len()).map(|i| {
            (
                outcome.human_to_robot[i].is_some(),
                outcome.human_has_partner[i],
            )
        });
        human.markers(&pen, human_state)?;
        let robot_state =
            (0..pair.robot.len()).map(|a| (outcome.robot_matched[a], outcome.robot_has_partner[a]));
        robot.markers(&pen, robot_state)?;
        human.labels(&pen)?;
        robot.labels(&pen)?;
        legend(&pen, outcome, (w / 2, h - pen.px(18.0)))
    }

    fn title(&self, pen: &Pen<'_, '_>, outcome: &Outcome) -> Result<(), RenderError> {
        let n = outcome.right.len();
        let title = format!(
            "{}   ·   method {}   ·   accuracy {:.3} ({} of {} human-view objects right)",
            self.pair.name,
            self.method,
            outcome.accuracy,
            outcome.right.iter().filter(|&&r| r).count(),
            n
        );
        // Shrunk to fit when a long scene name meets a narrow picture.
        let room = pen.size.width as i32 - pen.px(32.0);
        let width = pen.text_width(&title, TITLE_SIZE)?.max(1);
        let size = TITLE_SIZE * f64::from(room.min(width)) / f64::from(width);
        pen.text(
            &title,
            (pen.size.width as i32 / 2, pen.px(22.0)),
            size,
            BLACK,
            Pos::new(HPos::Center, VPos::Center),
        )
    }
}

/// What the prediction got right and wrong, by object index.
#[derive(Debug)]
pub(crate) struct Outcome {
    pub(crate) human_to_robot: Vec<Option<usize>>,
    /// Per human object: does the prediction agree with the ground truth
    /// (both "no partner" counts as agreement, as the accuracy metric has it)?
    pub(crate) right: Vec<bool>,
    pub(crate) human_has_partner: Vec<bool>,
    pub(crate) robot_matched: Vec<bool>,
    pub(crate) robot_has_partner: Vec<bool>,
    pub(crate) accuracy: f64,
}

impl Outcome {
    pub(crate) fn new(pair: &ScenePair, predicted: &[(u64, u64)]) -> Result<Self, RenderError> {
        let (human, robot) = (&pair.human, &pair.robot);
        let mut human_to_robot = vec![None; human.len()];
        let mut robot_matched = vec![false; robot.len()];
        for &(h, r) in predicted {
            let i = index(human, Side::Human, h)?;
            let a = index(robot, Side::Robot, r)?;
            human_to_robot[i] = Some(a);
            robot_matched[a] = true;
        }
        let truth: HashMap<u64, u64> = pair.ground_truth.iter().copied().collect();
        let mut robot_has_partner = vec![false; robot.len()];
        for &(_, r) in &pair.ground_truth {
            robot_has_partner[index(robot, Side::Robot, r)?] = true;
        }
        let human_ids: Vec<u64> = human.objects().iter().map(|o| o.id).collect();
        let right = human_ids
            .iter()
            .zip(&human_to_robot)
            .map(|(id, a)| truth.get(id).copied() == a.map(|a| robot.objects()[a].id))
            .collect();
        Ok(Self {
            human_to_robot,
            right,
            human_has_partner: human_ids.iter().map(|id| truth.contains_key(id)).collect(),
            robot_matched,
            robot_has_partner,
            accuracy: score_scene(&human_ids, predicted, &pair.ground_truth).accuracy,
        })
    }

    fn any_unmatched(&self) -> bool {
        self.human_to_robot.iter().any(Option::is_none) || self.robot_matched.contains(&false)
    }

    fn any_lone(&self) -> bool {
        self.human_has_partner.contains(&false) || self.robot_has_partner.contains(&false)
    }

    fn count(&self, right: bool) -> usize {
        self.human_to_robot
            .iter()
            .zip(&self.right)
            .filter(|(a, r)| a.is_some() && **r == right)
            .count()
    }
}

fn index(graph: &SceneGraph, side: Side, id: u64) -> Result<usize, RenderError> {
    graph
        .index_of(id)
        .ok_or(RenderError::UnknownPredictedId { side, id })
}

/// One view's panel: its frame and where each of its objects is drawn.
struct Panel<'g> {
    graph: &'g SceneGraph,
    rect: (i32, i32, i32, i32),
    points: Vec<(i32, i32)>,
}

impl<'g> Panel<'g> {
    fn new(
        pen: &Pen<'_, '_>,
        graph: &'g SceneGraph,
        projection: Projection,
        rect: (i32, i32, i32, i32),
    ) -> Result<Self, RenderError> {
        let projected: Vec<(f64, f64)> = graph
            .objects()
            .iter()
            .map(|o| projection.apply(o.position.coords.into()))
            .collect();
        let (left, top, right, bottom) = rect;
        // Room for the header above, and for the id labels that stand to
        // the right of the markers (track ids can be long).
        let mut widest = 0;
        for object in graph.objects() {
            widest = widest.max(pen.text_width(&object.id.to_string(), LABEL_SIZE)?);
        }
        let inner = (
            left + pen.px(24.0),
            top + pen.px(44.0),
            right - pen.px(16.0) - widest.max(pen.px(8.0)),
            bottom - pen.px(20.0),
        );
        let fit = Fit::new(&projected, inner);
        Ok(Self {
            graph,
            rect,
            points: projected.into_iter().map(|p| fit.pixel(p)).collect(),
        })
    }

    fn frame(
        &self,
        pen: &Pen<'_, '_>,
        name: &str,
        projection: Projection,
    ) -> Result<(), RenderError> {
        let (left, top, right, bottom) = self.rect;
        pen.draw(&Rectangle::new(
            [(left, top), (right, bottom)],
            FRAME.stroke_width(1),
        ))?;
        let header = format!("{name}: {} objects", self.graph.len());
        let y = top + pen.px(16.0);
        let at_left = Pos::new(HPos::Left, VPos::Center);
        pen.text(
            &header,
            (left + pen.px(10.0), y),
            HEADER_SIZE,
            BLACK,
            at_left,
        )?;
        // The caption only where it does not run into the header.
        let caption = projection.caption();
        let used = pen.text_width(&header, HEADER_SIZE)? + pen.text_width(caption, CAPTION_SIZE)?;
        if used + pen.px(40.0) > right - left {
            return Ok(());
        }
        let at_right = Pos::new(HPos::Right, VPos::Center);
        pen.text(
            caption,
            (right - pen.px(10.0), y),
            CAPTION_SIZE,
            CAPTION,
            at_right,
        )
    }

    /// The graph's own edges, faint: they show the structure the spatial
    /// term compares. A fully connected graph has none drawn (they would
    /// hide everything).
    fn edges(&self, pen: &Pen<'_, '_>) -> Result<(), RenderError> {
        for &(i, j) in self.graph.edges().unwrap_or_default() {
            pen.line(self.points[i], self.points[j], EDGE.to_rgba(), 1.0)?;
        }
        Ok(())
    }

    /// `state` gives, per object, (matched by the prediction, has a true
    /// partner).
    fn markers(
        &self,
        pen: &Pen<'_, '_>,
        state: impl Iterator<Item = (bool, bool)>,
    ) -> Result<(), RenderError> {
        for (&point, (matched, partnered)) in self.points.iter().zip(state) {
            pen.marker(point, matched, if partnered { PAIRED } else { LONE })?;
        }
        Ok(())
    }

    fn labels(&self, pen: &Pen<'_, '_>) -> Result<(), RenderError> {
        let above_right = Pos::new(HPos::Left, VPos::Bottom);
        for (object, &(x, y)) in self.graph.objects().iter().zip(&self.points) {
            let at = (x + pen.px(5.0), y - pen.px(4.0));
            pen.text(&object.id.to_string(), at, LABEL_SIZE, LABEL, above_right)?;
        }
        Ok(())
    }
}

/// A row of symbols with their meaning, centred on `centre`.
fn legend(pen: &Pen<'_, '_>, outcome: &Outcome, centre: (i32, i32)) -> Result<(), RenderError> {
    enum Symbol {
        /// A correspondence line, right or wrong.
        Line(bool),
        Marker(bool, RGBColor),
    }
    let mut items = vec![
        (
            Symbol::Line(true),
            format!("right match ({})", outcome.count(true)),
        ),
        (
            Symbol::Line(false),
            format!("wrong match ({})", outcome.count(false)),
        ),
        (Symbol::Marker(true, PAIRED), "matched".to_owned()),
    ];
    // Only the kinds of object this scene has: a symbol for nothing on
    // the picture would send the reader looking for it.
    if outcome.any_unmatched() {
        items.push((Symbol::Marker(false, PAIRED), "left unmatched".to_owned()));
    }
    if outcome.any_lone() {
        items.push((Symbol::Marker(true, LONE), "no true partner".to_owned()));
    }
    let (symbol, pad, spacing) = (pen.px(22.0), pen.px(6.0), pen.px(26.0));
    let widths = items
        .iter()
        .map(|(_, text)| pen.text_width(text, 13.0))
        .collect::<Result<Vec<_>, _>>()?;
    let total: i32 =
        widths.iter().map(|w| symbol + pad + w).sum::<i32>() + spacing * (items.len() as i32 - 1);
    let (mut x, y) = (centre.0 - total / 2, centre.1);
    for ((item, text), width) in items.iter().zip(widths) {
        match *item {
            Symbol::Line(right) => pen.correspondence((x, y), (x + symbol, y), right)?,
            Symbol::Marker(filled, colour) => pen.marker((x + symbol / 2, y), filled, colour)?,
        }
        let at = (x + symbol + pad, y);
        pen.text(text, at, 13.0, BLACK, Pos::new(HPos::Left, VPos::Center))?;
        x += symbol + pad + width + spacing;
    }
    Ok(())
}

/// Drawing primitives with sizes given for a 1200x600 picture and scaled
/// to the real one, so that a bigger picture is the same picture, sharper.
struct Pen<'a, 'b> {
    area: &'a Area<'b>,
    size: Size,
    scale: f64,
}

impl<'a, 'b> Pen<'a, 'b> {
    fn new(area: &'a Area<'b>, size: Size) -> Self {
        let scale = (f64::from(size.width) / 1200.0)
            .min(f64::from(size.height) / 600.0)
            .clamp(0.5, 4.0);
        Self { area, size, scale }
    }

    fn px(&self, v: f64) -> i32 {
        (v * self.scale).round() as i32
    }

    fn draw<E>(&self, element: &E) -> Result<(), RenderError>
    where
        for<'e> &'e E: PointCollection<'e, (i32, i32)>,
        E: Drawable<BitMapBackend<'b>>,
    {
        self.area.draw(element).map_err(drawing)
    }

    fn line(
        &self,
        from: (i32, i32),
        to: (i32, i32),
        colour: RGBAColor,
        width: f64,
    ) -> Result<(), RenderError> {
        let width = (width * self.scale).round().max(1.0) as u32;
        self.draw(&PathElement::new(
            vec![from, to],
            colour.stroke_width(width),
        ))
    }

    /// A line between matched objects: solid green if right, dashed red if
    /// wrong (dashed, so that readers who cannot tell red from green can
    /// still tell them apart).
    fn correspondence(
        &self,
        from: (i32, i32),
        to: (i32, i32),
        right: bool,
    ) -> Result<(), RenderError> {
        if right {
            return self.line(from, to, RIGHT.to_rgba(), 2.0);
        }
        let style = WRONG.stroke_width(self.px(2.0).max(1) as u32);
        let (dash, gap) = (self.px(9.0).max(2), self.px(4.0).max(1));
        self.draw(&DashedPathElement::new(vec![from, to], dash, gap, style))
    }

    /// A dot: filled for a matched object, hollow (white inside) for one
    /// left without partner.
    fn marker(&self, at: (i32, i32), filled: bool, colour: RGBColor) -> Result<(), RenderError> {
        let radius = self.px(5.0);
        if filled {
            self.draw(&Circle::new(at, radius, colour.filled()))
        } else {
            // A white disc on a coloured one: plotters' thick circle
            // outlines come out ragged.
            let ring = self.px(2.0).max(1);
            self.draw(&Circle::new(at, radius, colour.filled()))?;
            self.draw(&Circle::new(at, (radius - ring).max(1), WHITE.filled()))
        }
    }

    fn style(&self, size: f64, colour: RGBColor, pos: Pos) -> TextStyle<'static> {
        TextStyle {
            font: (font::FAMILY, size * self.scale).into_font(),
            color: colour.to_backend_color(),
            pos,
        }
    }

    fn text(
        &self,
        text: &str,
        at: (i32, i32),
        size: f64,
        colour: RGBColor,
        pos: Pos,
    ) -> Result<(), RenderError> {
        self.area
            .draw_text(text, &self.style(size, colour, pos), at)
            .map_err(drawing)
    }

    fn text_width(&self, text: &str, size: f64) -> Result<i32, RenderError> {
        let style = self.style(size, BLACK, Pos::new(HPos::Left, VPos::Top));
        let (w, _) = self
            .area
            .estimate_text_size(text, &style)
            .map_err(drawing)?;
        Ok(i32::try_from(w).unwrap_or(i32::MAX))
    }
}
