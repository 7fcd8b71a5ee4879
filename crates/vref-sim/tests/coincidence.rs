#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! `rigid` on views with nothing in common: every partner it gives is
//! wrong, so at most 1% of its answers may be `ok` (a partner with
//! confidence at least the matcher's ambiguity threshold, 0.5).
//!
//! Ignored: slow, and not met today. `tools/method-tables.sh` measures the
//! same on the reporting files' unrelated views (docs/method.md: 14% of
//! answers `ok` on the build that wrote it). Run with
//! `cargo test --release -p vref-sim --test coincidence -- --ignored`.

use vref_match::{Evaluation, Method, Params};
use vref_scene::ScenePair;
use vref_sim::unrelated::{across_scenes, random_clouds, shuffled};
use vref_sim::{Generator, Preset};

/// Answers given, and those `ok`, over `pairs`.
fn ok_answers(pairs: &[ScenePair]) -> (usize, usize) {
    let mut evaluation = Evaluation::new(&[Method::Rigid], Params::default()).unwrap();
    for pair in pairs {
        evaluation.add(pair).unwrap();
    }
    let answers = evaluation.answers(Method::Rigid);
    let ok = answers
        .iter()
        .filter(|a| a.matched && a.confidence >= 0.5)
        .count();
    (answers.len(), ok)
}

#[test]
#[ignore = "slow; the 1% target is not met yet (docs/method.md)"]
fn unrelated_views_are_rarely_answered_ok() {
    let mut sets: Vec<(String, Vec<ScenePair>)> = Vec::new();
    for (preset, seed) in [(Preset::Moi, 71), (Preset::Mrc, 72)] {
        let generator = Generator::new(preset.config(), seed).unwrap();
        let pairs: Vec<ScenePair> = generator.scenes(10).map(|s| s.unwrap().pair).collect();
        sets.push((format!("{preset:?} across"), across_scenes(&pairs).unwrap()));
        sets.push((
            format!("{preset:?} shuffled"),
            shuffled(&pairs, 73).unwrap(),
        ));
    }
    for objects in [8, 64, 256] {
        sets.push((
            format!("clouds of {objects}"),
            random_clouds(3, objects, 60, 74).unwrap(),
        ));
    }
    let (mut answers, mut ok) = (0, 0);
    let mut lines = Vec::new();
    for (name, pairs) in &sets {
        let (a, k) = ok_answers(pairs);
        answers += a;
        ok += k;
        lines.push(format!("{name}: {k} of {a}"));
    }
    assert!(
        ok * 100 <= answers,
        "{ok} of {answers} answers ok: {}",
        lines.join(", ")
    );
}
