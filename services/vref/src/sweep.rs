//! `vref eval --sweep`: accuracy against a noise level on generated scenes,
//! as a plot, and as a table or JSON lines. The sweep itself is
//! `vref_sim::Sweep`; this module only parses, reports and draws.

use std::path::Path;

use anyhow::{Context, anyhow};
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_match::{Method, Stat};
use vref_sim::{DEFAULT_LEVELS, Preset, Sweep, SweepError, SweepPoint, accuracy_curves};

use crate::cli::EvalArgs;
use crate::progress;
use crate::stdout;
use crate::table::Table;

/// Defaults of `--count` and `--seed`, as `--help` states them.
const DEFAULT_COUNT: u64 = 30;
const DEFAULT_SEED: u64 = 1;

pub fn run(args: &EvalArgs) -> Result<(), Failure> {
    // clap requires these with --sweep; checked again rather than trusted.
    let (Some(noise), Some(preset), Some(out)) =
        (args.sweep, args.preset.as_deref(), args.out.as_deref())
    else {
        return Err(anyhow!("--sweep needs --preset and --out")).bad_input();
    };
    let preset: Preset = preset.parse().context("--preset").bad_input()?;
    let (config, source) = Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    let mut params = config.matching;
    if let Some(beta) = args.beta {
        params.beta = beta;
    }
    let sweep = Sweep {
        noise,
        base: preset.config(),
        name: preset.name().to_owned(),
        levels: args
            .levels
            .clone()
            .unwrap_or_else(|| DEFAULT_LEVELS.to_vec()),
        count: args.count.unwrap_or(DEFAULT_COUNT),
        seed: args.seed.unwrap_or(DEFAULT_SEED),
        methods: if args.methods.is_empty() {
            Method::ALL.to_vec()
        } else {
            args.methods.clone()
        },
        params,
    };
    sweep.validate().map_err(blame)?;

    let progress = progress::generated(sweep.total_scenes());
    let points = sweep.run_with(|| progress.inc(1)).map_err(blame)?;
    progress.finish_and_clear();

    plot(&sweep, preset, &points, out)?;
    tracing::info!(out = %out.display(), "plot written");
    let text = if args.json {
        points
            .iter()
            .map(|p| format!("{}\n", json_line(p, &sweep, preset)))
            .collect()
    } else {
        table(&points, &sweep, preset)
    };
    stdout::print(&text)
}

/// Errors of the plan are the caller's; a scene that cannot be generated or
/// matched is the program's.
fn blame(error: SweepError) -> Failure {
    match error {
        SweepError::Scene { .. } | SweepError::Match { .. } => {
            Failure::Runtime(anyhow::Error::new(error))
        }
        SweepError::Params(_) => Failure::BadInput(anyhow::Error::new(error).context("--beta")),
        SweepError::BadLevel { .. } | SweepError::NoLevels => {
            Failure::BadInput(anyhow::Error::new(error).context("--levels"))
        }
        SweepError::NoScenes => Failure::BadInput(anyhow::Error::new(error).context("--count")),
        _ => Failure::BadInput(anyhow::Error::new(error)),
    }
}

fn plot(sweep: &Sweep, preset: Preset, points: &[SweepPoint], out: &Path) -> Result<(), Failure> {
    let series: Vec<(&str, Vec<(f64, f64)>)> = accuracy_curves(points)
        .into_iter()
        .map(|(method, curve)| (method.name(), curve))
        .collect();
    let what = sweep.noise.name().replace('-', " ");
    let title = format!(
        "{preset}: accuracy against {what} ({} scenes per level, seed {})",
        sweep.count, sweep.seed
    );
    let x_label = format!("{what} (factor on the preset's)");
    vref_viz::line_plot(&title, &x_label, "accuracy", &series, out)
        .context("drawing the plot")
        .runtime()
}

/// One `--json` line; field order is the documented contract's.
#[derive(serde::Serialize)]
struct JsonLine<'a> {
    method: &'a str,
    sweep: &'a str,
    level: f64,
    preset: &'a str,
    scenes: usize,
    accuracy: f64,
    precision: f64,
    recall: f64,
}

fn json_line(point: &SweepPoint, sweep: &Sweep, preset: Preset) -> String {
    let s = &point.summary;
    let line = JsonLine {
        method: point.method.name(),
        sweep: sweep.noise.name(),
        level: point.level,
        preset: preset.name(),
        scenes: s.scenes,
        accuracy: s.accuracy.mean,
        precision: s.precision.mean,
        recall: s.recall.mean,
    };
    serde_json::to_string(&line).unwrap_or_default()
}

fn table(points: &[SweepPoint], sweep: &Sweep, preset: Preset) -> String {
    let mut table = Table::new(&[
        "level",
        "method",
        "accuracy",
        "precision",
        "recall",
        "mean solve",
    ]);
    let stat = |st: Stat| format!("{:.4} ± {:.4}", st.mean, st.std);
    for p in points {
        let s = &p.summary;
        table.row(vec![
            format!("{}", p.level),
            p.method.name().to_owned(),
            stat(s.accuracy),
            stat(s.precision),
            stat(s.recall),
            format!("{:.1} us", p.mean_solve.as_secs_f64() * 1e6),
        ]);
    }
    format!(
        "{preset}, {}: {} scenes per level, seed {}\n{table}",
        sweep.noise, sweep.count, sweep.seed
    )
}
