//! `vref bench solver`: prints solver timings measured by
//! [`crate::bench_solver`].

use anyhow::{Context, anyhow};
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_match::{Method, Tier};

use crate::bench_solver::{Mode, Scenes, Timing, time_solver};
use crate::cli::BenchSolverArgs;
use crate::stdout;
use crate::table::Table;

pub fn solver(args: &BenchSolverArgs) -> Result<(), Failure> {
    if args.sizes.is_empty() {
        return Err(anyhow!("--sizes: give at least one size")).bad_input();
    }
    let (config, source) = Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    let params = config.matching;
    params.validate().context("configuration").bad_input()?;
    let methods = if args.methods.is_empty() {
        Method::ALL.to_vec()
    } else {
        args.methods.clone()
    };

    let tiers = if args.tiers.is_empty() {
        vec![Tier::Exact]
    } else {
        args.tiers.clone()
    };

    let mut timings = Vec::new();
    for &method in &methods {
        for &tier in &tiers {
            for &objects in &args.sizes {
                for mode in [Mode::Full, Mode::Incremental] {
                    let scenes = Scenes {
                        objects,
                        seed: args.seed,
                        noise: args.noise,
                        up: args.up_vectors,
                    };
                    let timing = time_solver(method, tier, scenes, mode, &params, args.repeats)
                        .with_context(|| format!("{method} ({tier}) at {objects} objects"))
                        .bad_input()?;
                    if args.json {
                        // One line at a time, so that a long run shows progress.
                        stdout::print(&format!("{}\n", json_line(&timing)))?;
                    }
                    timings.push(timing);
                }
            }
        }
    }
    if args.json {
        return Ok(());
    }
    let mut table = Table::new(&[
        "method",
        "tier",
        "objects",
        "mode",
        "median us",
        "p99 us",
        "iterations",
    ]);
    for t in &timings {
        table.row(vec![
            t.method.to_string(),
            t.tier.to_string(),
            t.objects.to_string(),
            t.mode.name().to_owned(),
            format!("{:.0}", t.median_us),
            format!("{:.0}", t.p99_us),
            t.iterations.to_string(),
        ]);
    }
    stdout::print(&format!(
        "{} repeats, seed {}, position noise {} m; incremental = update and solve after one object moved\n{table}",
        args.repeats, args.seed, args.noise
    ))
}

fn json_line(t: &Timing) -> serde_json::Value {
    serde_json::json!({
        "method": t.method.name(),
        "tier": t.tier.name(),
        "objects": t.objects,
        "position_noise_m": t.noise,
        "mode": t.mode.name(),
        "median_us": t.median_us,
        "p99_us": t.p99_us,
        "iterations": t.iterations,
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    fn args(tiers: Vec<Tier>) -> BenchSolverArgs {
        BenchSolverArgs {
            sizes: vec![4],
            methods: vec![Method::Sm],
            tiers,
            repeats: 1,
            seed: 1,
            noise: vref_sim::RigidScene::POSITION_NOISE,
            json: true,
            config: None,
            up_vectors: false,
        }
    }

    #[test]
    fn both_tiers_run_and_no_sizes_is_bad_input() {
        assert!(solver(&args(vec![Tier::Exact, Tier::Live])).is_ok());
        let mut none = args(vec![Tier::Live]);
        none.sizes.clear();
        assert!(matches!(solver(&none), Err(Failure::BadInput(_))));
        let mut negative = args(vec![Tier::Live]);
        negative.noise = -0.01;
        assert!(matches!(solver(&negative), Err(Failure::BadInput(_))));
    }

    #[test]
    fn json_lines_carry_the_documented_fields() {
        let timing = Timing {
            method: Method::Paper,
            tier: Tier::Live,
            objects: 64,
            noise: 0.02,
            mode: Mode::Incremental,
            median_us: 1.5,
            p99_us: 2.5,
            iterations: 7,
        };
        assert_eq!(
            json_line(&timing),
            serde_json::json!({"method": "paper", "tier": "live", "objects": 64,
                "position_noise_m": 0.02, "mode": "incremental", "median_us": 1.5,
                "p99_us": 2.5, "iterations": 7})
        );
    }
}
