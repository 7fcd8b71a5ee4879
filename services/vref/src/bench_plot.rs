//! `vref bench plot`: solve time against object count, log-log, from the
//! JSON lines of `vref bench solver --json` (any number of files: tiers,
//! runs) and of `tools/pygmtools_bench.py --json`.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, anyhow, bail};
use vref_logging::exit::{Blame, Failure};
use vref_viz::{Axes, Scale, line_plot_scaled};

use crate::cli::BenchPlotArgs;

/// Points of one curve, by object count.
type Curves = BTreeMap<String, BTreeMap<u64, f64>>;

pub fn plot(args: &BenchPlotArgs) -> Result<(), Failure> {
    let mut curves = Curves::new();
    for file in &args.solver {
        read_lines(file, &mut curves, |v| vref_point(v, &args.mode)).bad_input()?;
    }
    for file in &args.pygmtools {
        read_lines(file, &mut curves, pygmtools_point).bad_input()?;
    }
    if curves.is_empty() {
        return Err(anyhow!(
            "no {} timings in the files given (`vref bench solver --json` lines)",
            args.mode
        ))
        .bad_input();
    }
    let series: Vec<(String, Vec<(f64, f64)>)> = curves
        .into_iter()
        .map(|(name, points)| {
            let points = points.into_iter().map(|(n, us)| (n as f64, us)).collect();
            (name, points)
        })
        .collect();
    // Two powers of 2 of room left of the smallest size: the legend of
    // up to a dozen curves goes there instead of over them.
    let smallest = series
        .iter()
        .flat_map(|(_, p)| p.iter().map(|q| q.0))
        .fold(f64::INFINITY, f64::min);
    let axes = Axes {
        x: Scale::Log(2.0),
        y: Scale::Log(10.0),
        legend_room_from: smallest.is_finite().then_some(smallest / 4.0),
    };
    let title = format!(
        "{} solve time (affinities, solve, assignment), median",
        args.mode
    );
    line_plot_scaled(
        (&title, "objects per view", "microseconds"),
        &series,
        axes,
        &args.out,
    )
    .runtime()?;
    tracing::info!(out = %args.out.display(), curves = series.len(), "plot written");
    Ok(())
}

/// Reads JSON lines of `path`; `point` turns one into (curve, objects,
/// microseconds), or `None` to skip it.
fn read_lines(
    path: &Path,
    curves: &mut Curves,
    point: impl Fn(&serde_json::Value) -> anyhow::Result<Option<(String, u64, f64)>>,
) -> anyhow::Result<()> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    for (k, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let context = || format!("{} line {}", path.display(), k + 1);
        let value: serde_json::Value = serde_json::from_str(line).with_context(context)?;
        if let Some((curve, objects, us)) = point(&value).with_context(context)? {
            if !(us.is_finite() && us > 0.0) {
                return Err(anyhow!("time {us} is not positive")).with_context(context);
            }
            curves.entry(curve).or_default().insert(objects, us);
        }
    }
    Ok(())
}

fn field<'a>(v: &'a serde_json::Value, key: &str) -> anyhow::Result<&'a serde_json::Value> {
    v.get(key).ok_or_else(|| anyhow!("no field `{key}`"))
}

fn text<'a>(v: &'a serde_json::Value, key: &str) -> anyhow::Result<&'a str> {
    field(v, key)?
        .as_str()
        .ok_or_else(|| anyhow!("`{key}` is not a string"))
}

fn number(v: &serde_json::Value, key: &str) -> anyhow::Result<f64> {
    field(v, key)?
        .as_f64()
        .ok_or_else(|| anyhow!("`{key}` is not a number"))
}

fn objects(v: &serde_json::Value) -> anyhow::Result<u64> {
    match field(v, "objects")?.as_u64() {
        Some(n) if n > 0 => Ok(n),
        _ => bail!("`objects` is not a positive whole number"),
    }
}

/// `{"method", "tier", "objects", "mode", "median_us", ...}`: lines of
/// other modes are skipped.
fn vref_point(v: &serde_json::Value, mode: &str) -> anyhow::Result<Option<(String, u64, f64)>> {
    if text(v, "mode")? != mode {
        return Ok(None);
    }
    let name = format!("vref {} ({})", text(v, "method")?, text(v, "tier")?);
    Ok(Some((name, objects(v)?, number(v, "median_us")?)))
}

/// `{"method", "objects", "total_median_us", ...}`: affinity matrix and
/// solve together, as vref's full solve counts them.
fn pygmtools_point(v: &serde_json::Value) -> anyhow::Result<Option<(String, u64, f64)>> {
    let method = text(v, "method")?;
    // Lines of the script's --params defaults are a curve of their own.
    let name = match v.get("params").and_then(|p| p.as_str()) {
        Some("defaults") => format!("pygmtools {method} (its defaults)"),
        _ => format!("pygmtools {method}"),
    };
    Ok(Some((name, objects(v)?, number(v, "total_median_us")?)))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    #[test]
    fn vref_lines_of_the_mode_become_points_named_by_method_and_tier() {
        let line = serde_json::json!({"method": "rrwm", "tier": "exact", "objects": 32,
            "mode": "full", "median_us": 6600.0, "p99_us": 7200.0, "iterations": 20});
        assert_eq!(
            vref_point(&line, "full").unwrap(),
            Some(("vref rrwm (exact)".to_owned(), 32, 6600.0))
        );
        assert_eq!(vref_point(&line, "incremental").unwrap(), None);
        let broken = serde_json::json!({"method": "rrwm", "tier": "exact", "mode": "full"});
        assert!(vref_point(&broken, "full").is_err());
    }

    #[test]
    fn pygmtools_lines_count_affinities_and_solve() {
        let line = serde_json::json!({"method": "sm", "objects": 16,
            "total_median_us": 900.5, "solve_median_us": 100.0});
        assert_eq!(
            pygmtools_point(&line).unwrap(),
            Some(("pygmtools sm".to_owned(), 16, 900.5))
        );
        let defaults = serde_json::json!({"method": "rrwm", "params": "defaults",
            "objects": 8, "total_median_us": 10.0});
        assert_eq!(
            pygmtools_point(&defaults).unwrap().unwrap().0,
            "pygmtools rrwm (its defaults)"
        );
    }

    #[test]
    fn files_are_read_line_by_line_and_bad_lines_named() {
        let dir = tempfile::tempdir().unwrap();
        let good = dir.path().join("good.jsonl");
        std::fs::write(
            &good,
            "{\"method\":\"sm\",\"objects\":8,\"total_median_us\":5}\n\n{\"method\":\"sm\",\"objects\":16,\"total_median_us\":50}\n",
        )
        .unwrap();
        let mut curves = Curves::new();
        read_lines(&good, &mut curves, pygmtools_point).unwrap();
        assert_eq!(curves["pygmtools sm"].len(), 2);
        let bad = dir.path().join("bad.jsonl");
        std::fs::write(
            &bad,
            "{\"method\":\"sm\",\"objects\":8,\"total_median_us\":0}\n",
        )
        .unwrap();
        let error = read_lines(&bad, &mut curves, pygmtools_point).unwrap_err();
        assert!(format!("{error:#}").contains("line 1"), "{error:#}");
    }
}
