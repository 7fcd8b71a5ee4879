//! How far the front end's positions lie from BOP's ground-truth object
//! origins (`cam_t_m2c`), per dataset and camera: the distance, and its
//! parts along the object's ray (depth) and across it, as medians and
//! 90th percentiles over every measured object, for scenes 0-5, 6-11 and
//! all. Usage: `bop_positions DIR... [--centre-offset K]`.

use std::path::PathBuf;

use vref_import::{BopDataset, BopOptions, BopScene, MeasuredView};
use vref_perception::PerceptionSettings;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut dirs = Vec::new();
    let mut perception = PerceptionSettings::default();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--centre-offset" {
            perception.centre_offset = args.next().ok_or("value")?.parse()?;
        } else {
            dirs.push(PathBuf::from(a));
        }
    }
    let options = BopOptions {
        robot_image: 0,
        human_image: 1,
        perception,
        world_up: None,
    };
    println!(
        "dataset camera scenes objects | dist p50 p90 | along p50 (signed) | across p50  (mm)"
    );
    for dir in dirs {
        let dataset = BopDataset::open(&dir, "test")?;
        for (label, range) in [("0-5", 0..6), ("6-11", 6..12), ("all", 0..12)] {
            let mut rows: [Vec<[f64; 3]>; 2] = [Vec::new(), Vec::new()];
            for scene in dataset.scenes().iter().filter(|s| range.contains(&s.id)) {
                let measured = BopScene::measure(&dataset, scene, &options)?;
                for (c, (image, view)) in [(0, &measured.robot), (1, &measured.human)]
                    .into_iter()
                    .enumerate()
                {
                    let truth = scene
                        .load_view(image, options.perception.image_limit())?
                        .origins;
                    rows[c].extend(errors(view, &truth));
                }
            }
            for (c, name) in ["robot", "human"].iter().enumerate() {
                let r = &rows[c];
                let col = |k: usize| r.iter().map(|e| e[k]).collect::<Vec<_>>();
                println!(
                    "{} {name} {label} {} | {:.1} {:.1} | {:.1} | {:.1}",
                    dataset.name(),
                    r.len(),
                    1e3 * pct(col(0), 0.5),
                    1e3 * pct(col(0), 0.9),
                    1e3 * pct(col(1), 0.5),
                    1e3 * pct(col(2), 0.5),
                );
            }
        }
    }
    Ok(())
}

/// Per detection: distance to the truth, signed error along the truth's
/// ray (positive: measured beyond the origin), and across it.
fn errors<'a>(
    view: &'a MeasuredView,
    truth: &'a [[f64; 3]],
) -> impl Iterator<Item = [f64; 3]> + 'a {
    let known = view.detections.iter().zip(&view.instances);
    known.filter_map(|(d, &k)| Some((d, k?))).map(|(d, k)| {
        let t = truth[k];
        let e = [0, 1, 2].map(|i| d.position[i] - t[i]);
        let norm = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
        let along = (0..3).map(|i| e[i] * t[i] / norm).sum::<f64>();
        let dist = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        [dist, along, (dist * dist - along * along).max(0.0).sqrt()]
    })
}

fn pct(mut v: Vec<f64>, q: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(((v.len().max(1) - 1) as f64 * q).round() as usize)
        .copied()
        .unwrap_or(f64::NAN)
}
