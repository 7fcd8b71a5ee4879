#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{Picture, not_white};
use vref_viz::{
    Axes, RenderError, Scale, Size, line_plot, line_plot_scaled, render_line_plot,
    render_line_plot_scaled,
};

fn sweep() -> Vec<(&'static str, Vec<(f64, f64)>)> {
    let curve = |drop: f64| {
        (0..=10)
            .map(|k| {
                let noise = f64::from(k) * 2.0;
                (noise, (1.0 - drop * noise / 20.0).clamp(0.0, 1.0))
            })
            .collect()
    };
    vec![
        ("appearance", curve(0.9)),
        ("sm", curve(0.5)),
        ("rrwm", curve(0.2)),
        ("paper", curve(0.1)),
    ]
}

/// Pixels of the first series' colour (Okabe-Ito blue).
fn blue([r, g, b]: [u8; 3]) -> bool {
    r < 60 && (90..140).contains(&g) && b > 150
}

#[test]
fn renders_a_png_of_the_requested_size() {
    let size = Size::new(700, 420);
    let png = render_line_plot(
        "accuracy under noise",
        "noise (px)",
        "accuracy",
        &sweep(),
        size,
    )
    .unwrap();
    let picture = Picture::decode(&png);
    assert_eq!((picture.width, picture.height), (700, 420));
    assert!(picture.count(not_white) > 5000, "picture is blank");
    assert!(picture.count(blue) > 200, "first series not drawn");
}

#[test]
fn writes_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sweep.png");
    let series = vec![("paper".to_owned(), vec![(0.0, 1.0), (5.0, 0.8)])];
    line_plot("t", "x", "y", &series, &out).unwrap();
    let picture = Picture::decode(&std::fs::read(&out).unwrap());
    assert_eq!((picture.width, picture.height), (900, 560));
}

#[test]
fn draws_degenerate_data() {
    let size = Size::new(400, 300);
    let none: Vec<(&str, Vec<(f64, f64)>)> = Vec::new();
    render_line_plot("empty", "x", "y", &none, size).unwrap();
    let one_point = vec![("only", vec![(3.0, 0.5)])];
    render_line_plot("one point", "x", "y", &one_point, size).unwrap();
    let beyond_unit = vec![("big", vec![(0.0, -4.0), (1.0, 40.0)])];
    render_line_plot("beyond 0..1", "x", "y", &beyond_unit, size).unwrap();
}

#[test]
fn refuses_non_finite_points() {
    let series = vec![("sm", vec![(0.0, 1.0), (1.0, f64::NAN)])];
    let error = render_line_plot("t", "x", "y", &series, Size::new(400, 300)).unwrap_err();
    assert!(
        matches!(&error, RenderError::NonFinitePoint { series, index: 1, .. } if series == "sm"),
        "{error}"
    );
}

fn log_log() -> Axes {
    Axes {
        x: Scale::Log(2.0),
        y: Scale::Log(10.0),
        legend_room_from: None,
    }
}

#[test]
fn draws_times_against_sizes_on_log_axes() {
    let sizes = [8.0, 16.0, 32.0, 64.0];
    let series = vec![
        (
            "fast",
            sizes.iter().map(|&n: &f64| (n, 3.0 * n * n)).collect(),
        ),
        (
            "slow",
            sizes.iter().map(|&n: &f64| (n, 40.0 * n.powi(4))).collect(),
        ),
    ];
    let size = Size::new(700, 420);
    let png =
        render_line_plot_scaled(("solve time", "objects", "us"), &series, log_log(), size).unwrap();
    let picture = Picture::decode(&png);
    assert_eq!((picture.width, picture.height), (700, 420));
    assert!(picture.count(blue) > 200, "first series not drawn");
    // The same data on linear axes squeezes the fast curve onto the x
    // axis: the log picture differs.
    let linear = render_line_plot_scaled(
        ("solve time", "objects", "us"),
        &series,
        Axes::default(),
        size,
    )
    .unwrap();
    assert_ne!(png, linear);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("log.png");
    line_plot_scaled(("t", "x", "y"), &series, log_log(), &out).unwrap();
    assert!(out.exists());
}

#[test]
fn refuses_values_a_log_axis_cannot_show() {
    for bad in [0.0, -1.0] {
        let series = vec![("sm", vec![(8.0, 1.0), (16.0, bad)])];
        let error =
            render_line_plot_scaled(("t", "x", "y"), &series, log_log(), Size::new(400, 300))
                .unwrap_err();
        assert!(
            matches!(&error, RenderError::NonFinitePoint { index: 1, .. }),
            "{error}"
        );
    }
    // Zero is fine on a linear axis.
    let series = vec![("sm", vec![(8.0, 1.0), (16.0, 0.0)])];
    render_line_plot_scaled(
        ("t", "x", "y"),
        &series,
        Axes::default(),
        Size::new(400, 300),
    )
    .unwrap();
}
