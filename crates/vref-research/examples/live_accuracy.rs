//! Accuracy of the methods on the synthetic feeds' live world (the world
//! `vref demo`, `vref soak` and `vref bench query` run), scored against its
//! truth: 40 moments 1.7 s apart, both views measured at the same moment.
//! With `--objects` above the preset's own counts the world is scaled up as
//! the feeds scale it (`vref_feed::synthetic_world`): the cameras stand
//! farther away, so their position error grows while the objects' spacing
//! does not; the residual columns show how far the views' positions are
//! from one rigid motion.
//!
//! `cargo run --release -p vref-research --example live_accuracy -- --objects 0,32,64 --method rigid --method paper`
//! (0: the preset's own counts; the configuration is `vref`'s default
//! lookup, so `VREF_CONFIG` applies).
//!
//! With `--resume-after SECONDS`, `rigid` is also scored as the matcher's
//! live tier runs it: an engine solves each moment, then the views
//! `SECONDS` later (the solve that starts from the motions the first one
//! kept), against a full solve of those same later views. With `--chain
//! K` as well, the engine solves the views `SECONDS` apart K times after
//! each moment, each solve starting from the one before (as the matcher
//! chains them between full searches), and the last is scored.

use anyhow::Context;
use clap::Parser;
use vref_match::engine::Engine;
use vref_match::{
    ECE_BINS, Method, Params, Problem, RigidMotion, Solution, Tier, expected_calibration_error,
    median_spacing, score_scene, solve,
};
use vref_research::live::view_graph;
use vref_scene::{Limits, SceneGraph, Side};
use vref_sim::LiveWorld;

#[derive(Debug, Parser)]
struct Args {
    /// Objects in the world, comma-separated; 0 for the preset's own counts.
    #[arg(long, value_delimiter = ',', default_value = "0,32,64")]
    objects: Vec<usize>,
    /// Seed of the world (default: the configuration's `[feeds] seed`).
    #[arg(long)]
    seed: Option<u64>,
    /// Methods to score; repeat for several.
    #[arg(long, default_values = ["rigid", "paper"])]
    method: Vec<Method>,
    /// Also score `rigid`'s live-tier solve of the views this many seconds
    /// after each moment, started from that moment's solve.
    #[arg(long)]
    resume_after: Option<f64>,
    /// With `--resume-after`: how many solves, that many seconds apart,
    /// the engine chains after each moment's full solve; the last is
    /// scored. At most `[matching.live] rigid_full_every` - 1 of them
    /// are resumed ones.
    #[arg(long, default_value_t = 1)]
    chain: u64,
    /// Both views carry their camera's exact vertical, as the synthetic
    /// feeds publish it (`[feeds] up_vectors`).
    #[arg(long)]
    up_vectors: bool,
}

const MOMENTS: u64 = 40;

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let (mut config, _) = vref_config::Config::load(None).context("loading the configuration")?;
    if let Some(seed) = args.seed {
        config.feeds.seed = seed;
    }
    let params: Params = config.matching;
    let how = Observe {
        limits: Limits::default(),
        up_vectors: args.up_vectors,
    };
    println!(
        "objects  method  accuracy  precision  ece    unmatched  with partner  residual p50/p90  0.4 x spacing  solve p50"
    );
    for &n in &args.objects {
        let (_, world) = vref_feed::synthetic_world(&config.feeds, (n > 0).then_some(n))
            .with_context(|| format!("the live world with {n} objects"))?;
        let residuals = residuals(&world, &how)?;
        for &method in &args.method {
            let mut tally = Tally::default();
            let (mut unmatched, mut humans, mut partners) = (0, 0, 0);
            for k in 0..MOMENTS {
                let t = 1_000.0 + k as f64 * 1.7;
                let (human, robot) = views(&world, t, k, &how)?;
                let problem = Problem::new(&human, &robot, params.beta)?;
                let start = std::time::Instant::now();
                let solution = solve(method, &problem, &params)?;
                tally.solve_us.push(start.elapsed().as_secs_f64() * 1e6);
                let truth = world.truth(t);
                tally.add(&solution, &human, &robot, &truth);
                unmatched += solution.assignment.iter().filter(|a| a.is_none()).count();
                humans += human.len();
                partners += truth.len();
            }
            let scenes = tally.scenes as f64;
            println!(
                "{n:7}  {:6}  {:8.3}  {:9.3}  {:5.3}  {:9.2}  {:12.2}  {:7.3} / {:.3} m  {:.3} m  {:.0} us",
                method.to_string(),
                tally.accuracy / scenes,
                tally.precision / scenes,
                expected_calibration_error(&tally.answers, ECE_BINS),
                unmatched as f64 / humans as f64,
                partners as f64 / humans as f64,
                residuals.0,
                residuals.1,
                residuals.2,
                quantile(&mut tally.solve_us, 0.5),
            );
        }
        if let Some(dt) = args.resume_after {
            resumed(&world, &params, &how, n, dt, args.chain.max(1))?;
        }
    }
    Ok(())
}

/// Sums over scored solves.
#[derive(Default)]
struct Tally {
    accuracy: f64,
    precision: f64,
    scenes: usize,
    answers: Vec<(f64, bool)>,
    solve_us: Vec<f64>,
}

impl Tally {
    fn add(
        &mut self,
        solution: &Solution,
        human: &SceneGraph,
        robot: &SceneGraph,
        truth: &[(u64, u64)],
    ) {
        let ids: Vec<u64> = human.objects().iter().map(|o| o.id).collect();
        let predicted = solution.id_pairs(human, robot);
        let partner: std::collections::HashMap<u64, u64> = truth.iter().copied().collect();
        for ((&h, a), &c) in ids
            .iter()
            .zip(&solution.assignment)
            .zip(&solution.confidence)
        {
            let said = a.map(|j| robot.objects()[j].id);
            self.answers.push((c, said == partner.get(&h).copied()));
        }
        let score = score_scene(&ids, &predicted, truth);
        self.accuracy += score.accuracy;
        self.precision += score.precision;
        self.scenes += 1;
    }

    fn print(&mut self, objects: usize, name: &str) {
        let scenes = self.scenes.max(1) as f64;
        println!(
            "{objects:7}  {name:14}  {:8.3}  {:9.3}  {:5.3}  {:.0} us",
            self.accuracy / scenes,
            self.precision / scenes,
            expected_calibration_error(&self.answers, ECE_BINS),
            quantile(&mut self.solve_us, 0.5),
        );
    }
}

/// `rigid`'s live-tier solve `chain x dt` seconds after each moment, the
/// last of `chain` solves `dt` apart started from that moment's solve,
/// against a full solve of the same later views.
fn resumed(
    world: &LiveWorld,
    params: &Params,
    how: &Observe,
    objects: usize,
    dt: f64,
    chain: u64,
) -> anyhow::Result<()> {
    let (mut live, mut full) = (Tally::default(), Tally::default());
    let mut resumed = 0;
    for k in 0..MOMENTS {
        let t = 1_000.0 + k as f64 * 1.7;
        let (human, robot) = views(world, t, k, how)?;
        let mut engine = Engine::new(Method::Rigid, Tier::Live, *params)?;
        engine.update(Side::Human, &human)?;
        engine.update(Side::Robot, &robot)?;
        engine.solve()?;
        for step in 1..chain {
            let (human, robot) = views(world, t + step as f64 * dt, step * MOMENTS + k, how)?;
            engine.update(Side::Human, &human)?;
            engine.update(Side::Robot, &robot)?;
            engine.solve()?;
        }
        let later = t + chain as f64 * dt;
        let (human, robot) = views(world, later, chain * MOMENTS + k, how)?;
        let truth = world.truth(later);
        let start = std::time::Instant::now();
        engine.update(Side::Human, &human)?;
        engine.update(Side::Robot, &robot)?;
        let solution = engine.solve()?.0.clone();
        live.solve_us.push(start.elapsed().as_secs_f64() * 1e6);
        resumed += usize::from(engine.resumed());
        live.add(&solution, &human, &robot, &truth);
        let problem = Problem::new(&human, &robot, params.beta)?;
        let start = std::time::Instant::now();
        let solution = solve(Method::Rigid, &problem, params)?;
        full.solve_us.push(start.elapsed().as_secs_f64() * 1e6);
        full.add(&solution, &human, &robot, &truth);
    }
    let later = chain as f64 * dt;
    println!(
        "objects  {later:.3} s later ({chain} x {dt} s)  accuracy  precision  ece    solve p50 (update and solve)"
    );
    live.print(objects, "rigid, live");
    full.print(objects, "rigid, full");
    println!("         resumed {resumed} of {MOMENTS} live solves");
    Ok(())
}

/// How the views are measured: the graph's limits, and whether each view
/// carries its camera's up vector (`--up-vectors`).
struct Observe {
    limits: Limits,
    up_vectors: bool,
}

fn views(
    world: &LiveWorld,
    t: f64,
    frame: u64,
    how: &Observe,
) -> anyhow::Result<(SceneGraph, SceneGraph)> {
    let view = |side| view_graph(world, side, t, frame, &how.limits, how.up_vectors);
    Ok((view(Side::Human)?, view(Side::Robot)?))
}

/// Over the moments: median and 90th percentile of the distance between
/// each true pair under the rigid motion fitted to all true pairs, and the
/// median of `rigid`'s sigma (0.4 x the robot view's median
/// nearest-neighbour distance).
fn residuals(world: &LiveWorld, how: &Observe) -> anyhow::Result<(f64, f64, f64)> {
    let (mut all, mut sigmas) = (Vec::new(), Vec::new());
    for k in 0..MOMENTS {
        let t = 1_000.0 + k as f64 * 1.7;
        let (human, robot) = views(world, t, k, how)?;
        let position =
            |g: &SceneGraph, id: u64| g.objects().iter().find(|o| o.id == id).map(|o| o.position);
        let (from, to): (Vec<_>, Vec<_>) = world
            .truth(t)
            .into_iter()
            .filter_map(|(h, r)| Some((position(&human, h)?, position(&robot, r)?)))
            .unzip();
        if let Some(motion) = RigidMotion::fit(&from, &to, &vec![1.0; from.len()]) {
            all.extend(
                from.iter()
                    .zip(&to)
                    .map(|(f, t)| (motion.apply(f) - t).norm()),
            );
        }
        let points: Vec<_> = robot.objects().iter().map(|o| o.position).collect();
        if let Some(spacing) = median_spacing(&points) {
            sigmas.push(0.4 * spacing);
        }
    }
    Ok((
        quantile(&mut all, 0.5),
        quantile(&mut all, 0.9),
        quantile(&mut sigmas, 0.5),
    ))
}

fn quantile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let k = ((values.len() as f64 - 1.0) * q).round() as usize;
    values.get(k).copied().unwrap_or(f64::NAN)
}
