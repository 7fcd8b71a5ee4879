//! How much of `rigid`'s error is its search's: per dataset file, mean
//! accuracy and precision over scenes (as `vref eval` averages them) of
//! rigid's answers, of its assignment under the motion it found (before
//! abstention), and of its assignment under the true motion (the rigid fit
//! to the ground-truth pairs), once fitted to every true pair and once,
//! for each row, to every true pair but its own. These are what rigid's
//! costs would answer had the search not erred; the first is fitted to the
//! pairs it is judged on and flatters, the second does not.
//!
//! `cargo run --release -p vref-research --example rigid_ceiling -- FILE.jsonl...`

use anyhow::Context;
use vref_match::{
    Method, Params, Problem, RigidMotion, rigid_assignment_under, score_scene, solve,
};
use vref_research::truth;
use vref_scene::{Limits, ScenePair, read_dataset_file};

/// Sums of per-scene accuracy and precision.
#[derive(Default)]
struct Tally {
    accuracy: f64,
    precision: f64,
    scenes: usize,
}

impl Tally {
    fn add(&mut self, pair: &ScenePair, problem: &Problem, assignment: &[Option<usize>]) {
        let hid: Vec<u64> = pair.human.objects().iter().map(|o| o.id).collect();
        let rid: Vec<u64> = pair.robot.objects().iter().map(|o| o.id).collect();
        let predicted: Vec<(u64, u64)> = assignment
            .iter()
            .enumerate()
            .filter_map(|(i, a)| a.map(|j| (hid[i], rid[j])))
            .collect();
        debug_assert_eq!(hid.len(), problem.n);
        let score = score_scene(&hid, &predicted, &pair.ground_truth);
        self.accuracy += score.accuracy;
        self.precision += score.precision;
        self.scenes += 1;
    }

    fn line(&self, what: &str) -> String {
        let n = self.scenes.max(1) as f64;
        format!(
            "  {what:<28} accuracy {:.4}  precision {:.4}",
            self.accuracy / n,
            self.precision / n
        )
    }
}

fn main() -> anyhow::Result<()> {
    let files: Vec<String> = std::env::args().skip(1).collect();
    anyhow::ensure!(!files.is_empty(), "usage: rigid_ceiling FILE.jsonl...");
    let (config, _) = vref_config::Config::load(None).context("loading the configuration")?;
    let params: Params = config.matching;
    for file in &files {
        let pairs = read_dataset_file(file.as_ref(), Limits::default())
            .with_context(|| format!("reading {file}"))?;
        let (mut answered, mut own, mut truth, mut held_out) = (
            Tally::default(),
            Tally::default(),
            Tally::default(),
            Tally::default(),
        );
        let mut without_truth = 0;
        for pair in &pairs {
            let problem = Problem::new(&pair.human, &pair.robot, params.beta)?;
            let solution = solve(Method::Rigid, &problem, &params)?;
            // Scenes of under three true pairs have no true motion: every
            // line counts rigid's answer there.
            let partners = truth::true_partners(pair, &problem);
            let true_motion = |without| {
                let (from, to) = truth::true_pairs(&problem, &partners, without);
                truth::fit(&from, &to)
            };
            let Some(gt) = true_motion(None) else {
                without_truth += 1;
                for t in [&mut answered, &mut own, &mut truth, &mut held_out] {
                    t.add(pair, &problem, &solution.assignment);
                }
                continue;
            };
            answered.add(pair, &problem, &solution.assignment);
            let under_own = solution.motion.map_or_else(
                || solution.assignment.clone(),
                |m| rigid_assignment_under(&problem, &params, &m, &[]),
            );
            own.add(pair, &problem, &under_own);
            truth.add(
                pair,
                &problem,
                &rigid_assignment_under(&problem, &params, &gt, &[]),
            );
            // Each row under the true motion fitted without its own pair:
            // no row is judged by a motion fitted to it.
            let rows: Vec<RigidMotion> = (0..problem.n)
                .map(|i| true_motion(Some(i)).unwrap_or(gt))
                .collect();
            held_out.add(
                pair,
                &problem,
                &rigid_assignment_under(&problem, &params, &gt, &rows),
            );
        }
        println!(
            "{file}: {} scenes ({without_truth} with under three true pairs)",
            pairs.len()
        );
        println!("{}", answered.line("rigid as answered"));
        println!("{}", own.line("its motion, no abstention"));
        println!("{}", truth.line("true motion, no abstention"));
        println!("{}", held_out.line("true motion without the row"));
    }
    Ok(())
}
