//! What a dataset file's errors look like under its true motion (the rigid
//! fit to the ground-truth pairs): how the true pairs' residuals split
//! along the two cameras' rays and across them, how they grow with range,
//! whether they are biased along the rays (centroids of the visible
//! surface), how often appearance ranks the true partner first, and how
//! many objects have no partner. One line per file.
//!
//! `cargo run --release -p vref-research --example error_law -- FILE.jsonl...`

use anyhow::Context;
use vref_match::Problem;
use vref_research::truth;
use vref_scene::{Limits, read_dataset_file};

#[derive(Default)]
struct Tally {
    objects: usize,
    partnerless: usize,
    /// Per true pair: residual along the robot ray, along the human ray
    /// (moved), across both, the two ranges, and the spacing of its scene.
    along_robot: Vec<f64>,
    along_human: Vec<f64>,
    across: Vec<f64>,
    range_robot: Vec<f64>,
    range_human: Vec<f64>,
    spacing: Vec<f64>,
    /// Appearance of the true partner below the row's best, per true pair.
    appearance_gap: Vec<f64>,
    /// Partnerless human objects whose best robot object is itself
    /// partnerless (a look-alike the other camera alone sees).
    partnerless_best_free: usize,
}

fn main() -> anyhow::Result<()> {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    anyhow::ensure!(!paths.is_empty(), "usage: error_law FILE.jsonl...");
    for path in paths {
        let pairs = read_dataset_file(path.as_ref(), Limits::default())
            .with_context(|| format!("reading {path}"))?;
        let mut t = Tally::default();
        for pair in &pairs {
            let problem = Problem::new(&pair.human, &pair.robot, 0.01)?;
            let true_j = truth::true_partners(pair, &problem);
            let partnered_robot: Vec<bool> =
                (0..problem.m).map(|j| true_j.contains(&Some(j))).collect();
            let (from, to) = truth::true_pairs(&problem, &true_j, None);
            let Some(gt) = truth::fit(&from, &to) else {
                continue;
            };
            let spacing = vref_match::median_spacing(&problem.robot_positions).unwrap_or(f64::NAN);
            let m = problem.m;
            for (i, tj) in true_j.iter().enumerate() {
                t.objects += 1;
                let row = &problem.appearance[i * m..(i + 1) * m];
                let best = row.iter().copied().fold(f64::MIN, f64::max);
                let Some(j) = *tj else {
                    t.partnerless += 1;
                    let arg = row.iter().position(|&a| a == best).unwrap_or_default();
                    t.partnerless_best_free += usize::from(!partnered_robot[arg]);
                    continue;
                };
                t.appearance_gap.push(best - row[j]);
                let h = problem.human_positions[i];
                let q = problem.robot_positions[j];
                let r = q - gt.apply(&h);
                let u = q.coords.normalize();
                let w = (gt.rotation * h.coords).normalize();
                t.along_robot.push(r.dot(&u));
                t.along_human.push(r.dot(&w));
                // Across both rays: the component normal to their plane.
                let normal = u.cross(&w);
                t.across.push(if normal.norm() > 1e-9 {
                    r.dot(&normal.normalize()).abs()
                } else {
                    (r - u * r.dot(&u)).norm()
                });
                t.range_robot.push(q.coords.norm());
                t.range_human.push(h.coords.norm());
                t.spacing.push(spacing);
            }
        }
        report(&path, &t);
    }
    Ok(())
}

fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn quantile(values: &[f64], q: f64) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let at = ((v.len() as f64 - 1.0) * q).round() as usize;
    v.get(at).copied().unwrap_or(f64::NAN)
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// Root mean square of `values[k] / scale[k]`.
fn rms_over(values: &[f64], scale: &[f64]) -> f64 {
    (values
        .iter()
        .zip(scale)
        .map(|(v, s)| (v / s).powi(2))
        .sum::<f64>()
        / values.len().max(1) as f64)
        .sqrt()
}

fn report(path: &str, t: &Tally) {
    let abs = |v: &[f64]| v.iter().map(|x| x.abs()).collect::<Vec<_>>();
    let near: Vec<bool> = t
        .range_robot
        .iter()
        .map(|&r| r <= median(&t.range_robot))
        .collect();
    let split = |v: &[f64], keep: bool| -> Vec<f64> {
        v.iter()
            .zip(&near)
            .filter(|(_, n)| **n == keep)
            .map(|(x, _)| x.abs())
            .collect()
    };
    let first = t.appearance_gap.iter().filter(|&&g| g <= 0.0).count();
    let within = t.appearance_gap.iter().filter(|&&g| g <= 0.23).count();
    let pairs = t.appearance_gap.len().max(1) as f64;
    println!(
        "{path}: {} objects, {:.1}% without partner ({} of them best-matched to a partnerless robot object); \
         true partner first by appearance {:.1}%, within 0.23 of the row best {:.1}%; \
         residual median |along robot ray| {:.3} m (near half {:.3}, far half {:.3}), \
         |along human ray| {:.3} m, across both {:.3} m, spacing {:.3} m; \
         bias along robot ray {:+.3} m, along human ray {:+.3} m; \
         rms along ray / range: robot {:.3}, human {:.3}; median range robot {:.2} m, human {:.2} m; \
         tails of |across| over its median: 90% {:.2}, 99% {:.2} (a Gaussian's 2.44, 3.82); \
         of |along robot ray|: 90% {:.2}, 99% {:.2}",
        t.objects,
        100.0 * t.partnerless as f64 / t.objects.max(1) as f64,
        t.partnerless_best_free,
        100.0 * first as f64 / pairs,
        100.0 * within as f64 / pairs,
        median(&abs(&t.along_robot)),
        median(&split(&t.along_robot, true)),
        median(&split(&t.along_robot, false)),
        median(&abs(&t.along_human)),
        median(&t.across),
        median(&t.spacing),
        mean(&t.along_robot),
        mean(&t.along_human),
        rms_over(&t.along_robot, &t.range_robot),
        rms_over(&t.along_human, &t.range_human),
        median(&t.range_robot),
        median(&t.range_human),
        quantile(&t.across, 0.9) / median(&t.across),
        quantile(&t.across, 0.99) / median(&t.across),
        quantile(&abs(&t.along_robot), 0.9) / median(&abs(&t.along_robot)),
        quantile(&abs(&t.along_robot), 0.99) / median(&abs(&t.along_robot)),
    );
}
