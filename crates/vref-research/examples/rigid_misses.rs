//! Diagnoses `rigid`'s wrong partners on a dataset file: for each, whether
//! the object truly has no partner, how far the answer's motion is from
//! the true one, and the residuals and appearance of the answer against
//! the true partner.
//!
//! `cargo run --release -p vref-research --example rigid_misses -- FILE.jsonl`

use anyhow::Context;
use vref_match::{Method, Params, Problem, RigidMotion, solve};
use vref_research::truth;
use vref_scene::{Limits, read_dataset_file};

fn main() -> anyhow::Result<()> {
    let path = std::env::args()
        .nth(1)
        .context("usage: rigid_misses FILE.jsonl")?;
    let (config, _) = vref_config::Config::load(None).context("loading the configuration")?;
    let params: Params = config.matching;
    let pairs = read_dataset_file(path.as_ref(), Limits::default())?;
    for (s, pair) in pairs.iter().enumerate() {
        let problem = Problem::new(&pair.human, &pair.robot, params.beta)?;
        let solution = solve(Method::Rigid, &problem, &params)?;
        let partners = truth::true_partners(pair, &problem);
        let true_j = |i: usize| partners[i];
        let (from, to) = truth::true_pairs(&problem, &partners, None);
        let Some(gt) = truth::fit(&from, &to) else {
            continue;
        };
        let (pf, pt): (Vec<_>, Vec<_>) = solution
            .assignment
            .iter()
            .enumerate()
            .filter_map(|(i, a)| {
                a.map(|j| (problem.human_positions[i], problem.robot_positions[j]))
            })
            .unzip();
        let pm = RigidMotion::fit(&pf, &pt, &vec![1.0; pf.len()]);
        let motion_gap = pm.map_or(f64::NAN, |pm| {
            problem
                .human_positions
                .iter()
                .map(|p| (pm.apply(p) - gt.apply(p)).norm())
                .sum::<f64>()
                / problem.n as f64
        });
        let spacing = vref_match::median_spacing(&problem.robot_positions).unwrap_or(f64::NAN);
        let gt_rms = gt.rms(&from, &to);
        let m = problem.m;
        let mut lines = Vec::new();
        for i in 0..problem.n {
            let said = solution.assignment[i];
            let tj = true_j(i);
            if said == tj {
                continue;
            }
            let moved = gt.apply(&problem.human_positions[i]);
            let Some(j) = said else {
                // A partner missed: the object was answered "no partner".
                if let Some(t) = tj {
                    let row = &problem.appearance[i * m..(i + 1) * m];
                    let amax = row.iter().copied().fold(f64::MIN, f64::max);
                    lines.push(format!(
                        "  h{i} -> none conf {:.3}; truth j{t}: r {:.3} a {:.3} (row max {amax:.3})",
                        solution.confidence[i],
                        (moved - problem.robot_positions[t]).norm(),
                        row[t]
                    ));
                }
                continue;
            };
            let r_said = (moved - problem.robot_positions[j]).norm();
            let a_said = problem.appearance[i * m + j];
            let other = match tj {
                Some(t) => format!(
                    "truth j{t}: r {:.3} a {:.3}",
                    (moved - problem.robot_positions[t]).norm(),
                    problem.appearance[i * m + t]
                ),
                None => "truth none".into(),
            };
            let taken = (0..problem.n)
                .find(|&k| true_j(k) == Some(j))
                .map_or("free".to_string(), |k| format!("partner of h{k}"));
            let amax = problem.appearance[i * m..(i + 1) * m]
                .iter()
                .copied()
                .fold(f64::MIN, f64::max);
            lines.push(format!(
                "  h{i} -> j{j} ({taken}) conf {:.3}: r {r_said:.3} a {a_said:.3} (row max {amax:.3}); {other}",
                solution.confidence[i]
            ));
        }
        if !lines.is_empty() {
            let matched = solution.assignment.iter().filter(|a| a.is_some()).count();
            println!(
                "scene {s} n{} m{} partners {} matched {matched}: motion gap {motion_gap:.3} m, spacing {spacing:.3}, true rms {gt_rms:.3}",
                problem.n,
                problem.m,
                from.len()
            );
            for l in lines {
                println!("{l}");
            }
        }
    }
    Ok(())
}
