//! Diagnosis of vref's own segments on rendered BOP scenes: per view, the
//! segments against the ground-truth instances (`mask_visib`, at least
//! 150 visible pixels), each instance classed by its best segment:
//! `ok` (IoU >= 0.5, what `vref import bop --segment` keeps), `missed`
//! (no segment covers a tenth of it), `part` (the segment covering most
//! of it covers less than half of it: cut low or split), `merged` (that
//! segment covers half of it or more but is mostly something else: its
//! neighbour or the floor), plus the share of its pixels above the seed
//! height and its height above the fitted plane.
//!
//! cargo run --release -p vref-import --example bop_segment_diag -- DIR FIRST LAST ['JSON' [HUMAN_C]]
//!
//! JSON overrides `[segmentation]` defaults (before the per-camera
//! scaling); HUMAN_C the headset's `pixel` c (default the config's).
//! `VERBOSE=1` prints every lost instance, and every false segment with
//! the share of it that lies on some instance (a fragment of an object).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::PathBuf;

use vref_import::BopDataset;
use vref_perception::{
    LabelImage, PerceptionSettings, RgbdFrame, Segmentation, SegmentationSettings, Segmenter,
};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = PathBuf::from(&args[1]);
    let first: u32 = args[2].parse().unwrap();
    let last: u32 = args[3].parse().unwrap();
    let mut settings = serde_json::to_value(SegmentationSettings::default()).unwrap();
    if let Some(text) = args.get(4) {
        let over: serde_json::Value = serde_json::from_str(text).unwrap();
        for (k, v) in over.as_object().unwrap() {
            settings[k] = v.clone();
        }
    }
    let settings: SegmentationSettings = serde_json::from_value(settings).unwrap();
    settings.validate().unwrap();
    let mut perception = PerceptionSettings::default();
    if let Some(c) = args.get(5) {
        perception.human.pixel.c = c.parse().unwrap();
    }
    let verbose = std::env::var_os("VERBOSE").is_some();
    let dataset = BopDataset::open(&dir, "test").unwrap();
    let mut totals = [[0usize; 6]; 2];
    println!("scene view segs gt ok missed part merged false | median height cm (ok / lost)");
    for scene in dataset
        .scenes()
        .iter()
        .filter(|s| (first..=last).contains(&s.id))
    {
        for (c, (image, pixel)) in [(0, perception.robot.pixel), (1, perception.human.pixel)]
            .into_iter()
            .enumerate()
        {
            let s = settings.for_camera(pixel);
            let view = scene.load_view(image, perception.image_limit()).unwrap();
            let frame = RgbdFrame {
                colour: &view.colour,
                depth: &view.depth,
                intrinsics: view.intrinsics,
                up: None,
            };
            let mut labels = LabelImage::new(1, 1);
            let result = Segmenter::new(s).segment(&frame, &mut labels).unwrap();
            let plane = match result {
                Segmentation::Objects { plane, .. } => Some(plane),
                Segmentation::NoSupport(_) => None,
            };
            let (w, _) = labels.dimensions();
            let n = result.objects();
            let k = view.intrinsics;
            let metres = view.depth.metres_per_unit();
            let height = |i: usize| -> Option<(f64, f64)> {
                let p = plane?;
                let d = f64::from(view.depth.pixels().as_raw()[i]) * metres;
                if d <= 0.0 {
                    return None;
                }
                let (u, v) = ((i % w as usize) as f64, (i / w as usize) as f64);
                let x = (u - k.cx()) / k.fx() * d;
                let y = (v - k.cy()) / k.fy() * d;
                let h = p.normal[0] * x + p.normal[1] * y + p.normal[2] * d + p.offset;
                Some((h, d))
            };
            let raw = labels.as_raw();
            let mut seg_area = vec![0usize; n + 1];
            for &l in raw {
                seg_area[l as usize] += 1;
            }
            let mut seg_has_truth = vec![false; n + 1];
            let mut counts = [0usize; 6];
            let mut heights_ok = Vec::new();
            let mut heights_lost = Vec::new();
            for (g, mask) in view.masks.iter().enumerate() {
                let mut inter = vec![0usize; n + 1];
                let mut area = 0usize;
                let mut hs = Vec::new();
                let mut above_seed = 0usize;
                for (i, (&m, &l)) in mask.as_raw().iter().zip(raw).enumerate() {
                    if m == 0 {
                        continue;
                    }
                    area += 1;
                    inter[l as usize] += 1;
                    if let Some((h, d)) = height(i) {
                        hs.push(h);
                        let cut = s.min_height_m.max(s.plane_tolerance_m * d * d);
                        above_seed += usize::from(h > cut);
                    }
                }
                if area < 150 {
                    continue;
                }
                hs.sort_by(f64::total_cmp);
                let top = hs.get(hs.len() * 9 / 10).copied().unwrap_or(0.0);
                let mut best_iou = 0.0f64;
                let mut best_cover = (0usize, 0usize);
                for l in 1..=n {
                    let union = area + seg_area[l] - inter[l];
                    let iou = inter[l] as f64 / union as f64;
                    if iou >= 0.5 {
                        seg_has_truth[l] = true;
                    }
                    best_iou = best_iou.max(iou);
                    if inter[l] > best_cover.0 {
                        best_cover = (inter[l], l);
                    }
                }
                let cover = best_cover.0 as f64 / area as f64;
                let purity = if best_cover.1 > 0 {
                    best_cover.0 as f64 / seg_area[best_cover.1] as f64
                } else {
                    0.0
                };
                let class = if best_iou >= 0.5 {
                    0
                } else if cover < 0.1 {
                    1
                } else if cover < 0.5 {
                    2
                } else {
                    3
                };
                counts[class] += 1;
                counts[5] += 1;
                if class == 0 {
                    heights_ok.push(top);
                } else {
                    heights_lost.push(top);
                }
                if verbose && class != 0 {
                    let depth = hs.len();
                    println!(
                        "  {:06} {} gt{g:2} obj{:2} px {area:6} depth-px {depth:6} top {:5.1} cm above-seed {:4.2} | best iou {best_iou:.2} cover {cover:.2} purity {purity:.2} [{}]",
                        scene.id,
                        ["robot", "human"][c],
                        view.object_ids[g],
                        100.0 * top,
                        above_seed as f64 / depth.max(1) as f64,
                        ["ok", "missed", "part", "merged"][class]
                    );
                }
            }
            counts[4] = (1..=n).filter(|&l| !seg_has_truth[l]).count();
            if verbose {
                // Each false segment: how much of it lies on some
                // instance (a fragment of an object) or on none (the
                // support, or something unlabelled), and where it is.
                let mut on_truth = vec![0usize; n + 1];
                let mut sum_uv = vec![(0usize, 0usize); n + 1];
                let mut hs: Vec<Vec<f64>> = vec![Vec::new(); n + 1];
                for (i, &l) in raw.iter().enumerate() {
                    if l == 0 || seg_has_truth[l as usize] {
                        continue;
                    }
                    let l = l as usize;
                    on_truth[l] += usize::from(view.masks.iter().any(|m| m.as_raw()[i] != 0));
                    sum_uv[l].0 += i % w as usize;
                    sum_uv[l].1 += i / w as usize;
                    if let Some((h, _)) = height(i) {
                        hs[l].push(h);
                    }
                }
                for l in (1..=n).filter(|&l| !seg_has_truth[l]) {
                    let a = seg_area[l].max(1);
                    hs[l].sort_by(f64::total_cmp);
                    let median = hs[l].get(hs[l].len() / 2).copied().unwrap_or(f64::NAN);
                    println!(
                        "  {:06} {} false seg {l:2} px {:6} on instances {:4.2} at ({:4}, {:4}) median height {:5.1} cm",
                        scene.id,
                        ["robot", "human"][c],
                        seg_area[l],
                        on_truth[l] as f64 / a as f64,
                        sum_uv[l].0 / a,
                        sum_uv[l].1 / a,
                        100.0 * median
                    );
                }
            }
            let med = |mut v: Vec<f64>| {
                v.sort_by(f64::total_cmp);
                v.get(v.len() / 2).map_or(f64::NAN, |x| 100.0 * x)
            };
            println!(
                "{:06} {} {n:3} {:3} {:3} {:3} {:3} {:3} {:3} | {:.1} / {:.1}{}",
                scene.id,
                ["robot", "human"][c],
                counts[5],
                counts[0],
                counts[1],
                counts[2],
                counts[3],
                counts[4],
                med(heights_ok),
                med(heights_lost),
                if plane.is_none() { " NO PLANE" } else { "" }
            );
            for (t, x) in totals[c].iter_mut().zip(counts) {
                *t += x;
            }
        }
    }
    for (c, t) in totals.iter().enumerate() {
        println!(
            "total {}: gt {} ok {} missed {} part {} merged {} false segments {}",
            ["robot", "human"][c],
            t[5],
            t[0],
            t[1],
            t[2],
            t[3],
            t[4]
        );
    }
}
