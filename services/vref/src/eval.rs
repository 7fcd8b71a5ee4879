use std::fs::File;
use std::io::BufReader;

use anyhow::{Context, anyhow};
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_match::{Evaluation, Method, MethodReport};
use vref_scene::DatasetReader;

use crate::cli::EvalArgs;
use crate::progress;
use crate::stdout;
use crate::table::Table;

pub fn run(args: &EvalArgs) -> Result<(), Failure> {
    // clap's "input" group guarantees --dataset or --sweep.
    let Some(dataset_path) = args.dataset.as_deref() else {
        return crate::sweep::run(args);
    };
    let (config, source) = Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    let mut params = config.matching;
    if let Some(beta) = args.beta {
        params.beta = beta;
    }
    let methods = if args.methods.is_empty() {
        Method::ALL.to_vec()
    } else {
        args.methods.clone()
    };
    let mut evaluation = Evaluation::new(&methods, params)
        .context("--beta")
        .bad_input()?
        .with_tier(args.tier)
        .with_ok_rule(config.matcher.ok_rule());

    let file = File::open(dataset_path)
        .with_context(|| format!("opening {}", dataset_path.display()))
        .bad_input()?;
    let progress = progress::scenes(dataset_path);
    for pair in DatasetReader::new(BufReader::new(file), config.scene.limits()) {
        let pair = pair
            .with_context(|| format!("reading {}", dataset_path.display()))
            .bad_input()?;
        evaluation
            .add(&pair)
            .with_context(|| format!("scene {:?}", pair.name))
            .bad_input()?;
        progress.inc(1);
    }
    progress.finish_and_clear();
    if evaluation.scenes() == 0 {
        return Err(anyhow!("{} holds no scenes", dataset_path.display())).bad_input();
    }

    if let Some(path) = &args.answers {
        write_answers(&evaluation, &methods, path)?;
    }
    let dataset = dataset_path.display().to_string();
    let reports = evaluation.reports();
    if args.json {
        let lines: String = reports
            .iter()
            .map(|r| format!("{}\n", json_line(r, &dataset, args.tier)))
            .collect();
        stdout::print(&lines)?;
    } else {
        stdout::print(&table(&reports, &format!("{dataset} ({} tier)", args.tier)))?;
    }
    Ok(())
}

/// One `--json` line; field order is the documented contract's.
#[derive(serde::Serialize)]
struct JsonLine<'a> {
    method: &'a str,
    tier: &'a str,
    dataset: &'a str,
    scenes: usize,
    accuracy: f64,
    precision: f64,
    recall: f64,
    accuracy_std: f64,
    precision_std: f64,
    recall_std: f64,
    mean_solve_us: f64,
    ece: f64,
}

fn json_line(report: &MethodReport, dataset: &str, tier: vref_match::Tier) -> String {
    let s = &report.summary;
    let line = JsonLine {
        method: report.method.name(),
        tier: tier.name(),
        dataset,
        scenes: s.scenes,
        accuracy: s.accuracy.mean,
        precision: s.precision.mean,
        recall: s.recall.mean,
        accuracy_std: s.accuracy.std,
        precision_std: s.precision.std,
        recall_std: s.recall.std,
        mean_solve_us: report.mean_solve.as_secs_f64() * 1e6,
        ece: report.ece,
    };
    serde_json::to_string(&line).unwrap_or_default()
}

fn table(reports: &[MethodReport], dataset: &str) -> String {
    let scenes = reports.first().map_or(0, |r| r.summary.scenes);
    let mut table = Table::new(&[
        "method",
        "accuracy",
        "precision",
        "recall",
        "ECE",
        "mean solve",
    ]);
    for r in reports {
        let s = &r.summary;
        let stat = |st: vref_match::Stat| format!("{:.4} ± {:.4}", st.mean, st.std);
        table.row(vec![
            r.method.name().to_owned(),
            stat(s.accuracy),
            stat(s.precision),
            stat(s.recall),
            format!("{:.4}", r.ece),
            format!("{:.1} us", r.mean_solve.as_secs_f64() * 1e6),
        ]);
    }
    format!("{dataset}: {scenes} scenes\n{table}")
}

/// One line of `--answers`.
#[derive(serde::Serialize)]
struct AnswerLine<'a> {
    method: &'a str,
    #[serde(flatten)]
    answer: &'a vref_match::RowAnswer,
}

fn write_answers(
    evaluation: &Evaluation,
    methods: &[Method],
    path: &std::path::Path,
) -> Result<(), Failure> {
    use std::io::Write;
    let write = || -> anyhow::Result<()> {
        let mut out = std::io::BufWriter::new(File::create(path)?);
        for &method in methods {
            for answer in evaluation.answers(method) {
                let line = AnswerLine {
                    method: method.name(),
                    answer,
                };
                serde_json::to_writer(&mut out, &line)?;
                out.write_all(b"\n")?;
            }
        }
        out.flush()?;
        Ok(())
    };
    write()
        .with_context(|| format!("writing {}", path.display()))
        .runtime()
}
