//! Curves of one measure against one parameter, one per method: accuracy
//! against noise, say.

use std::ops::Range;
use std::path::Path;

use plotters::prelude::*;

use crate::canvas::{self, Area, drawing};
use crate::{RenderError, Size, font};

/// Size of the pictures [`line_plot`] writes.
pub const LINE_PLOT_SIZE: Size = Size::new(900, 560);

/// Colours that stay apart for colour-blind readers (Okabe and Ito),
/// then a grey and a wine for plots of more than seven curves.
const PALETTE: [RGBColor; 9] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(140, 140, 140),
    RGBColor(136, 34, 85),
];

/// How an axis maps values to positions.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Scale {
    #[default]
    Linear,
    /// Logarithmic: equal steps for equal factors; ticks at powers of
    /// the base (2 for object counts, 10 for times). Values must be
    /// positive.
    Log(f64),
}

impl Scale {
    fn to_axis(self, v: f64) -> f64 {
        match self {
            Scale::Linear => v,
            Scale::Log(base) => v.ln() / base.ln(),
        }
    }

    fn value_at(self, v: f64) -> f64 {
        match self {
            Scale::Linear => v,
            Scale::Log(base) => base.powf(v),
        }
    }
}

/// The scales of both axes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Axes {
    pub x: Scale,
    pub y: Scale,
    /// Start the x axis here (data units) when that is below the data:
    /// room on the left, where the legend then goes, for plots with many
    /// curves that fill every corner.
    pub legend_room_from: Option<f64>,
}

/// Writes a line plot of `series` (name, points) to `out` as a PNG of
/// [`LINE_PLOT_SIZE`]. The y axis spans 0 to 1 when every value lies
/// there (accuracies, precisions), else the values' range.
pub fn line_plot<S: AsRef<str>>(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(S, Vec<(f64, f64)>)],
    out: &Path,
) -> Result<(), RenderError> {
    let png = render_line_plot(title, x_label, y_label, series, LINE_PLOT_SIZE)?;
    canvas::write(out, &png)
}

/// [`line_plot`] with the axes' scales given, e.g. log-log for times
/// against sizes.
pub fn line_plot_scaled<S: AsRef<str>>(
    (title, x_label, y_label): (&str, &str, &str),
    series: &[(S, Vec<(f64, f64)>)],
    axes: Axes,
    out: &Path,
) -> Result<(), RenderError> {
    let png = render_line_plot_scaled((title, x_label, y_label), series, axes, LINE_PLOT_SIZE)?;
    canvas::write(out, &png)
}

/// [`line_plot`] as PNG bytes of any size.
pub fn render_line_plot<S: AsRef<str>>(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(S, Vec<(f64, f64)>)],
    size: Size,
) -> Result<Vec<u8>, RenderError> {
    render_line_plot_scaled((title, x_label, y_label), series, Axes::default(), size)
}

/// [`line_plot_scaled`] as PNG bytes of any size. A point that is not
/// finite, or not positive on a log axis, is an error.
pub fn render_line_plot_scaled<S: AsRef<str>>(
    labels: (&str, &str, &str),
    series: &[(S, Vec<(f64, f64)>)],
    axes: Axes,
    size: Size,
) -> Result<Vec<u8>, RenderError> {
    let mut placed: Vec<(&str, Vec<(f64, f64)>)> = Vec::with_capacity(series.len());
    for (name, points) in series {
        let mut moved = Vec::with_capacity(points.len());
        for (index, &(x, y)) in points.iter().enumerate() {
            let p = (axes.x.to_axis(x), axes.y.to_axis(y));
            if !(x.is_finite() && y.is_finite() && p.0.is_finite() && p.1.is_finite()) {
                return Err(RenderError::NonFinitePoint {
                    series: name.as_ref().to_owned(),
                    index,
                    x,
                    y,
                });
            }
            moved.push(p);
        }
        placed.push((name.as_ref(), moved));
    }
    canvas::render_png(size, |area| draw(area, size, labels, &placed, axes))
}

/// Draws `series`, whose points are already in axis units (logarithms on
/// a log axis).
fn draw(
    area: &Area<'_>,
    size: Size,
    (title, x_label, y_label): (&str, &str, &str),
    series: &[(&str, Vec<(f64, f64)>)],
    axes: Axes,
) -> Result<(), RenderError> {
    let scale = (f64::from(size.width) / 900.0)
        .min(f64::from(size.height) / 560.0)
        .clamp(0.5, 4.0);
    let px = |v: f64| (v * scale).round() as u32;
    let points = || series.iter().flat_map(|(_, p)| p.iter().copied());
    let room = axes.legend_room_from.map(|x| axes.x.to_axis(x));
    let x_range = match axes.x {
        Scale::Linear => padded(points().map(|p| p.0).chain(room), 0.0),
        Scale::Log(_) => whole_powers(points().map(|p| p.0).chain(room)),
    };
    let y_range = match axes.y {
        Scale::Log(_) => whole_powers(points().map(|p| p.1)),
        Scale::Linear if points().all(|(_, y)| (0.0..=1.0).contains(&y)) => {
            // A little beyond [0, 1], so that a marker at 0 or 1 is not cut.
            -0.02..1.02
        }
        Scale::Linear => padded(points().map(|p| p.1), 0.05),
    };
    // On a log axis one tick per power, at the whole numbers of the axis.
    let labels = |range: &Range<f64>, scale: Scale, default: usize| match scale {
        Scale::Linear => default,
        Scale::Log(_) => ((range.end - range.start).round() as usize + 1).max(2),
    };
    let x_labels = labels(&x_range, axes.x, 10);
    let y_labels = labels(&y_range, axes.y, 10);

    let mut chart = ChartBuilder::on(area)
        .caption(title, (font::FAMILY, 22.0 * scale))
        .margin(px(18.0))
        .x_label_area_size(px(48.0))
        .y_label_area_size(px(62.0))
        .build_cartesian_2d(x_range.clone(), y_range.clone())
        .map_err(drawing)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style((font::FAMILY, 16.0 * scale))
        .label_style((font::FAMILY, 13.0 * scale))
        .x_labels(x_labels)
        .y_labels(y_labels)
        .x_label_formatter(&|v| scaled_tick(*v, axes.x))
        .y_label_formatter(&|v| scaled_tick(*v, axes.y))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(225, 225, 230))
        .draw()
        .map_err(drawing)?;

    let stroke = px(2.5).max(1);
    for (k, (name, points)) in series.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let legend_width = px(24.0) as i32;
        chart
            .draw_series(
                LineSeries::new(points.iter().copied(), colour.filled().stroke_width(stroke))
                    .point_size(px(3.5)),
            )
            .map_err(drawing)?
            .label(*name)
            .legend(move |(x, y)| {
                PathElement::new(
                    vec![(x, y), (x + legend_width, y)],
                    colour.stroke_width(stroke),
                )
            });
    }
    if !series.is_empty() {
        chart
            .configure_series_labels()
            .position(match room {
                Some(_) => SeriesLabelPosition::UpperLeft,
                None => emptiest_corner(points(), &x_range, &y_range),
            })
            .label_font((font::FAMILY, 14.0 * scale))
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(190, 190, 196))
            .draw()
            .map_err(drawing)?;
    }
    Ok(())
}

/// A tick value without float noise or trailing zeros: 0.3, not
/// 0.30000000000000004; 2, not 2.0.
fn tick(value: f64) -> String {
    let text = format!("{value:.4}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_owned()
    } else {
        text.to_owned()
    }
}

/// A tick label in data units: on a log axis the power the position
/// stands for, to two significant digits (1000, 32, 0.5).
fn scaled_tick(value: f64, scale: Scale) -> String {
    match scale {
        Scale::Linear => tick(value),
        Scale::Log(_) => {
            let v = scale.value_at(value);
            let digits = v.abs().log10().floor() as i32;
            let unit = 10f64.powi(digits - 1);
            tick((v / unit).round() * unit)
        }
    }
}

/// The smallest range of whole numbers that holds the values (log axes:
/// from one power of the base to another), at least one unit long.
fn whole_powers(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if lo > hi {
        return 0.0..1.0;
    }
    let (lo, hi) = (lo.floor(), hi.ceil());
    if hi > lo { lo..hi } else { lo..lo + 1.0 }
}

/// The values' range widened by `margin` of its length on each side; a
/// single value (or none) gets a range around it.
fn padded(values: impl Iterator<Item = f64>, margin: f64) -> Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if lo > hi {
        return 0.0..1.0;
    }
    if lo == hi {
        let half = (lo.abs() * 0.1).max(0.5);
        return lo - half..hi + half;
    }
    let pad = (hi - lo) * margin;
    lo - pad..hi + pad
}

/// The corner of the plot with the fewest points near it, for the legend.
fn emptiest_corner(
    points: impl Iterator<Item = (f64, f64)>,
    x: &Range<f64>,
    y: &Range<f64>,
) -> SeriesLabelPosition {
    // Accuracy curves fall from the upper left, so the upper right is the
    // usual winner and wins ties.
    let corners = [
        (SeriesLabelPosition::UpperRight, (true, true)),
        (SeriesLabelPosition::LowerLeft, (false, false)),
        (SeriesLabelPosition::LowerRight, (true, false)),
        (SeriesLabelPosition::UpperLeft, (false, true)),
    ];
    let mut counts = [0usize; 4];
    for (px, py) in points {
        let fx = (px - x.start) / (x.end - x.start);
        let fy = (py - y.start) / (y.end - y.start);
        for (count, (_, (right, upper))) in counts.iter_mut().zip(&corners) {
            let near_x = if *right { fx > 0.55 } else { fx < 0.45 };
            let near_y = if *upper { fy > 0.55 } else { fy < 0.45 };
            if near_x && near_y {
                *count += 1;
            }
        }
    }
    let best = (0..corners.len())
        .min_by_key(|&k| (counts[k], k))
        .unwrap_or(0);
    corners[best].0.clone()
}
