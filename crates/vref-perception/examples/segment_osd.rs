//! Tuning aid: segments every scene of an OSD-layout folder and prints
//! each scene's scores, the means per scene kind and over the tuning and
//! held-aside halves (scene number not = 0 mod 5, and = 0 mod 5).
//!
//! cargo run --release -p vref-perception --example segment_osd -- DIR ['{"crease": 0.3}']
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;
use std::time::Instant;

use vref_perception::segment::score::{ImageScore, MeanScore, score_image};
use vref_perception::*;

fn kind(n: u32) -> &'static str {
    match n {
        0..=16 => "boxes",
        17..=24 => "stacked",
        25..=32 => "occluded",
        _ => "cylinders",
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = Path::new(&args[1]);
    let mut settings = serde_json::to_value(SegmentationSettings::default()).unwrap();
    if let Some(text) = args.get(2) {
        let over: serde_json::Value = serde_json::from_str(text).unwrap();
        for (k, v) in over.as_object().unwrap() {
            settings[k] = v.clone();
        }
    }
    let settings: SegmentationSettings = serde_json::from_value(settings).unwrap();
    settings.validate().unwrap();
    let camera: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("../camera.json")).unwrap())
            .unwrap();
    let f = |k: &str| camera[k].as_f64().unwrap();
    let intrinsics = Intrinsics::new(f("fx"), f("fy"), f("cx"), f("cy")).unwrap();
    let mut scenes: Vec<(u32, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .map(|name| (name.trim_start_matches("learn").parse().unwrap(), name))
        .collect();
    scenes.sort();
    let mut segmenter = Segmenter::new(settings);
    let mut labels = LabelImage::new(1, 1);
    let mut all: Vec<(u32, ImageScore)> = Vec::new();
    let mut times = Vec::new();
    let verbose = std::env::var_os("VERBOSE").is_some();
    let save = std::env::var_os("SAVE");
    for (n, name) in &scenes {
        let scene = dir.join(name);
        let colour = load_colour(
            &scene.join("rgb.png"),
            vref_perception::ImageLimit::default(),
        )
        .unwrap();
        let depth = DepthImage::new(
            load_depth(
                &scene.join("depth.png"),
                vref_perception::ImageLimit::default(),
            )
            .unwrap(),
            0.001,
        )
        .unwrap();
        let truth = load_depth(
            &scene.join("label.png"),
            vref_perception::ImageLimit::default(),
        )
        .unwrap();
        let frame = RgbdFrame {
            colour: &colour,
            depth: &depth,
            intrinsics,
            up: None,
        };
        let start = Instant::now();
        let result = segmenter.segment(&frame, &mut labels).unwrap();
        times.push(start.elapsed().as_secs_f64() * 1e3);
        let s = score_image(&labels, &truth, 640, 480, 20).unwrap();
        if verbose {
            println!(
                "{name:9} {:9} objects {:2}/{:2} overlap {:.3} boundary {:.3} p75 {:.3} {:?}",
                kind(*n),
                s.predicted_objects,
                s.gt_objects,
                s.overlap.f,
                s.boundary.f,
                s.p75,
                match result {
                    Segmentation::NoSupport(r) => Some(r),
                    _ => None,
                }
            );
        }
        if let Some(out) = &save {
            let path = Path::new(out).join(format!("{name}.png"));
            segment::overlay(&colour, &labels).save(path).unwrap();
            let gt: Vec<u16> = truth.iter().map(|&t| if t >= 20 { t } else { 0 }).collect();
            let path = Path::new(out).join(format!("{name}_gt.png"));
            segment::overlay(&colour, &gt).save(path).unwrap();
        }
        all.push((*n, s));
    }
    times.sort_by(f64::total_cmp);
    let line = |label: &str, pick: &dyn Fn(u32) -> bool| {
        let scores: Vec<ImageScore> = all
            .iter()
            .filter(|(n, _)| pick(*n))
            .map(|(_, s)| *s)
            .collect();
        let m = MeanScore::of(&scores);
        let worst = scores.iter().map(|s| s.overlap.f).fold(1.0, f64::min);
        println!(
            "{label:10} n {:2} overlap P {:.3} R {:.3} F {:.3} boundary F {:.3} p75 {:.3} worst overlap F {:.3}",
            m.images,
            m.overlap.precision,
            m.overlap.recall,
            m.overlap.f,
            m.boundary.f,
            m.p75,
            worst
        );
    };
    for k in ["boxes", "stacked", "occluded", "cylinders"] {
        line(k, &|n| kind(n) == k);
    }
    line("tune", &|n| n % 5 != 0);
    line("held", &|n| n % 5 == 0);
    line("all", &|_| true);
    println!(
        "time median {:.2} ms max {:.2} ms",
        times[times.len() / 2],
        times[times.len() - 1]
    );
}
