//! `vref bench solver`: prints solver timings measured by
//! `vref_match::bench`.

use anyhow::{Context, anyhow};
use vref_config::Config;
use vref_match::Method;
use vref_match::bench::{Mode, Timing, time_solver};

use crate::cli::BenchSolverArgs;
use crate::failure::{Blame, Failure};
use crate::stdout;
use crate::table::Table;

pub fn solver(args: &BenchSolverArgs) -> Result<(), Failure> {
    match args.tier.as_str() {
        "exact" => {}
        "live" => {
            return Err(anyhow!(
                "--tier live: the live solver tier is not built yet (only exact)"
            ))
            .bad_input();
        }
        other => {
            return Err(anyhow!("--tier: unknown tier `{other}` (expected exact)")).bad_input();
        }
    }
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

    let mut timings = Vec::new();
    for &method in &methods {
        for &objects in &args.sizes {
            for mode in [Mode::Full, Mode::Incremental] {
                let timing = time_solver(method, objects, mode, &params, args.repeats, args.seed)
                    .with_context(|| format!("{method} at {objects} objects"))
                    .bad_input()?;
                if args.json {
                    // One line at a time, so that a long run shows progress.
                    stdout::print(&format!("{}\n", json_line(&timing)))?;
                }
                timings.push(timing);
            }
        }
    }
    if args.json {
        return Ok(());
    }
    let mut table = Table::new(&[
        "method",
        "objects",
        "mode",
        "median us",
        "p99 us",
        "iterations",
    ]);
    for t in &timings {
        table.row(vec![
            t.method.to_string(),
            t.objects.to_string(),
            t.mode.name().to_owned(),
            format!("{:.0}", t.median_us),
            format!("{:.0}", t.p99_us),
            t.iterations.to_string(),
        ]);
    }
    stdout::print(&format!(
        "tier exact, {} repeats, seed {}; incremental = full solve of the moved scene (no incremental engine yet)\n{table}",
        args.repeats, args.seed
    ))
}

fn json_line(t: &Timing) -> serde_json::Value {
    serde_json::json!({
        "method": t.method.name(),
        "tier": "exact",
        "objects": t.objects,
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

    fn args(tier: &str) -> BenchSolverArgs {
        BenchSolverArgs {
            sizes: vec![4],
            methods: vec![Method::Sm],
            tier: tier.to_owned(),
            repeats: 1,
            seed: 1,
            json: true,
            config: None,
        }
    }

    #[test]
    fn the_live_tier_and_unknown_tiers_are_bad_input() {
        for tier in ["live", "fast"] {
            match solver(&args(tier)) {
                Err(Failure::BadInput(e)) => assert!(e.to_string().contains("tier"), "{e}"),
                other => panic!("{tier}: {other:?}"),
            }
        }
    }

    #[test]
    fn json_lines_carry_the_documented_fields() {
        let timing = Timing {
            method: Method::Paper,
            objects: 64,
            mode: Mode::Incremental,
            median_us: 1.5,
            p99_us: 2.5,
            iterations: 7,
        };
        assert_eq!(
            json_line(&timing),
            serde_json::json!({"method": "paper", "tier": "exact", "objects": 64,
                "mode": "incremental", "median_us": 1.5, "p99_us": 2.5, "iterations": 7})
        );
    }
}
