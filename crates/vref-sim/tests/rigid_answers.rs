#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! Writes `rigid`'s answers (`RowAnswer` JSON lines, with margin, fit and
//! significance) on the data sets of docs/method.md, for choosing the
//! coincidence constants on the training files and reporting on the rest
//! without the release build of `vref` (the same `Evaluation` as `vref
//! eval`). Ignored; run from the repository with
//! `DIAG_OUT=DIR cargo test -p vref-sim --test rigid_answers -- --ignored diag`:
//! training files by default (sim seeds 100-109 pooled per preset, or per
//! seed with `DIAG_PERSEED=1`; external lines 1-20; BOP scenes 0-5),
//! reporting files with `DIAG_REPORT=1`; unrelated views of each (seed 11
//! for training clouds, 12 for reporting); `DIAG_ONLY=real|null`;
//! `DIAG_NOGATE=1` turns the coincidence rule off (`chance_rule = false`).
use std::io::Write;
use vref_match::{Evaluation, Method, Params};
use vref_scene::{Limits, ScenePair, read_dataset_file};
use vref_sim::unrelated::{across_scenes, random_clouds, shuffled};
use vref_sim::{Generator, Preset};

fn dump(name: &str, pairs: &[ScenePair], params: &Params) {
    let mut evaluation = Evaluation::new(&[Method::Rigid], *params).unwrap();
    let t = std::time::Instant::now();
    for pair in pairs {
        evaluation.add(pair).unwrap();
    }
    let dir = std::env::var("DIAG_OUT").unwrap_or("/tmp/r2/out".into());
    std::fs::create_dir_all(&dir).unwrap();
    let mut f = std::fs::File::create(format!("{dir}/{name}.jsonl")).unwrap();
    for a in evaluation.answers(Method::Rigid) {
        serde_json::to_writer(&mut f, a).unwrap();
        f.write_all(b"\n").unwrap();
    }
    eprintln!(
        "{name}: {} scenes {:.1}s",
        pairs.len(),
        t.elapsed().as_secs_f64()
    );
}

#[test]
#[ignore]
fn diag() {
    let mut params = Params::default();
    if std::env::var("DIAG_NOGATE").is_ok() {
        params.rigid.chance_rule = false;
    }
    let report = std::env::var("DIAG_REPORT").is_ok();
    let perseed = std::env::var("DIAG_PERSEED").is_ok();
    let mut real: Vec<(String, Vec<ScenePair>)> = Vec::new();
    let seeds: Vec<u64> = if report {
        (1..=5).collect()
    } else {
        (100..=109).collect()
    };
    for preset in [Preset::Moi, Preset::Mrc] {
        let mut all = Vec::new();
        for &seed in &seeds {
            let g = Generator::new(preset.config(), seed).unwrap();
            let pairs: Vec<ScenePair> = g.scenes(30).map(|s| s.unwrap().pair).collect();
            if report || perseed {
                real.push((format!("{preset:?}{seed}"), pairs.clone()));
            }
            all.push(pairs);
        }
        if !report && !perseed {
            real.push((format!("{preset:?}-train"), all.concat()));
        }
    }
    for family in ["moi", "mrc"] {
        let path = format!("../../../shared/data/external/{family}-ext.jsonl");
        let pairs = read_dataset_file(path.as_ref(), Limits::default()).unwrap();
        let (train, rep) = pairs.split_at(20);
        real.push((
            format!("{family}-ext"),
            if report { rep.to_vec() } else { train.to_vec() },
        ));
    }
    for family in ["table", "floor"] {
        let path = format!("../../../data/bop-{family}.jsonl");
        let pairs = read_dataset_file(path.as_ref(), Limits::default()).unwrap();
        let keep: Vec<ScenePair> = pairs
            .into_iter()
            .filter(|p| {
                let k: u32 = p.name.rsplit('/').next().unwrap().parse().unwrap();
                if report {
                    (6..=11).contains(&k)
                } else {
                    k <= 5
                }
            })
            .collect();
        real.push((format!("bop-{family}"), keep));
    }
    let only = std::env::var("DIAG_ONLY").unwrap_or_default();
    for (name, pairs) in &real {
        if only.is_empty() || only.contains("real") {
            dump(name, pairs, &params);
        }
    }
    if !(only.is_empty() || only.contains("null")) {
        return;
    }
    for (name, pairs) in &real {
        let first: Vec<ScenePair> = if name.ends_with("-train") {
            pairs[..30].to_vec()
        } else {
            pairs.clone()
        };
        dump(
            &format!("null-{name}-across"),
            &across_scenes(&first).unwrap(),
            &params,
        );
        dump(
            &format!("null-{name}-shuffled"),
            &shuffled(&first, 7).unwrap(),
            &params,
        );
    }
    let seed = if report { 12 } else { 11 };
    for objects in [8, 32, 64, 128, 256] {
        dump(
            &format!("null-clouds-{objects}"),
            &random_clouds(20, objects, 60, seed).unwrap(),
            &params,
        );
    }
}
