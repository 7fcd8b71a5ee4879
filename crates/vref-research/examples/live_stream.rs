//! The matcher's live engine over a continuous 30 Hz stream of the
//! synthetic feeds' world (the world `vref demo` runs), each view updated
//! in turn and solved after every update as the matcher does, against a
//! full solve of the same two views. Every human object of every solve is
//! scored against the world's truth at that moment, with the status the
//! service would give it (`OkRule`, the default): how often each is `ok`
//! with a wrong partner, or `no_match` though the robot sees its object.
//!
//! `cargo run --release -p vref-research --example live_stream -- --seconds 300`
//!
//! The human view is taken at the frame's time and the robot's half a
//! frame later, so that the two feeds' frames interleave as two
//! free-running cameras' do. `--list` prints each wrong `ok`.

use anyhow::Context;
use clap::Parser;
use vref_match::engine::Engine;
use vref_match::{Method, OkRule, Params, Problem, Solution, Tier, Verdict, solve};
use vref_research::live::view_graph;
use vref_scene::{Limits, SceneGraph, Side};

#[derive(Debug, Parser)]
struct Args {
    /// Seconds since the Unix epoch the stream starts at (the world's
    /// clock, as the feeds run it).
    #[arg(long, default_value_t = 1_796_689_000.0)]
    start: f64,
    /// Seconds of frames.
    #[arg(long, default_value_t = 300.0)]
    seconds: f64,
    /// Objects in the world (the demo's tests use 8).
    #[arg(long, default_value_t = 8)]
    objects: usize,
    /// Views without their camera's up vector (the feeds carry it by
    /// default, `[feeds] up_vectors`).
    #[arg(long)]
    no_up_vectors: bool,
    /// Print each wrong `ok`.
    #[arg(long)]
    list: bool,
}

const FRAME_S: f64 = 1.0 / 30.0;

/// Answers of one way of solving, by what the service would say.
#[derive(Debug, Default)]
struct Tally {
    answers: usize,
    right_ok: usize,
    wrong_ok: usize,
    right_no_match: usize,
    wrong_no_match: usize,
}

impl Tally {
    fn add(&mut self, verdict: Verdict, right: bool) {
        self.answers += 1;
        match (verdict, right) {
            (Verdict::Ok, true) => self.right_ok += 1,
            (Verdict::Ok, false) => self.wrong_ok += 1,
            (Verdict::NoMatch, true) => self.right_no_match += 1,
            (Verdict::NoMatch, false) => self.wrong_no_match += 1,
            _ => {}
        }
    }

    fn print(&self, name: &str) {
        println!(
            "{name:6}  {:7}  {:8}  {:8}  {:14}  {:14}",
            self.answers, self.right_ok, self.wrong_ok, self.right_no_match, self.wrong_no_match
        );
    }
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let (config, _) = vref_config::Config::load(None).context("loading the configuration")?;
    let params: Params = config.matching;
    let (_, world) =
        vref_feed::synthetic_world(&config.feeds, Some(args.objects)).context("the live world")?;
    let rule = OkRule::default();
    let mut engine = Engine::new(Method::Rigid, Tier::Live, params)?;
    let (mut live, mut full) = (Tally::default(), Tally::default());
    let mut latest: [Option<SceneGraph>; 2] = [None, None];
    let frames = (args.seconds / FRAME_S) as u64;
    for frame in 0..frames {
        for (k, side) in [Side::Human, Side::Robot].into_iter().enumerate() {
            let t = args.start + (frame as f64 + 0.5 * k as f64) * FRAME_S;
            let graph = view_graph(
                &world,
                side,
                t,
                frame,
                &Limits::default(),
                !args.no_up_vectors,
            )?;
            engine.update(side, &graph)?;
            latest[k] = Some(graph);
            let [Some(human), Some(robot)] = &latest else {
                continue;
            };
            let truth = world.truth(t);
            let resumed = {
                let (solution, _, _) = engine.solve()?;
                score(solution, human, robot, &truth, &rule, &mut live)
            };
            let problem = Problem::new(human, robot, params.beta)?;
            let whole = solve(Method::Rigid, &problem, &params)?;
            let searched = score(&whole, human, robot, &truth, &rule, &mut full);
            if args.list {
                for (row, status) in resumed.iter().chain(&searched).enumerate() {
                    if let Some(s) = status {
                        let by = if row < resumed.len() { "live" } else { "full" };
                        println!("t={:.3} {by}: {s}", t % 1000.0);
                    }
                }
            }
        }
    }
    println!("solve   answers  right ok  wrong ok  right no_match  wrong no_match");
    live.print("live");
    full.print("full");
    Ok(())
}

/// Adds each human object's answer to `tally`; returns, per row, a line
/// for each wrong `ok`.
fn score(
    solution: &Solution,
    human: &SceneGraph,
    robot: &SceneGraph,
    truth: &[(u64, u64)],
    rule: &OkRule,
    tally: &mut Tally,
) -> Vec<Option<String>> {
    human
        .objects()
        .iter()
        .enumerate()
        .map(|(row, object)| {
            let want = truth.iter().find(|(h, _)| *h == object.id).map(|p| p.1);
            let got = solution.assignment[row].map(|j| robot.objects()[j].id);
            let confidence = solution.confidence[row];
            let verdict = solution.verdict(row, confidence, rule);
            tally.add(verdict, got == want);
            (verdict == Verdict::Ok && got != want).then(|| {
                format!(
                    "human {} ok with robot {got:?} at {confidence:.3}, truth {want:?}",
                    object.id
                )
            })
        })
        .collect()
}
