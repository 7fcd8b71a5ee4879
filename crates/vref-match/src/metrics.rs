use std::collections::{HashMap, HashSet};

/// Accuracy, precision and recall of one scene (ALGORITHMS.md, Metrics).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneScore {
    pub accuracy: f64,
    pub precision: f64,
    pub recall: f64,
}

/// Scores the predicted (human id, robot id) pairs of one scene against its
/// ground truth. `human_ids` are all objects of the human view: one whose
/// prediction and truth are both "no partner" counts as right.
///
/// Recall of a scene with no true pairs is 1 (nothing to find) *(choice:
/// ALGORITHMS.md leaves it open)*.
pub fn score_scene(
    human_ids: &[u64],
    predicted: &[(u64, u64)],
    ground_truth: &[(u64, u64)],
) -> SceneScore {
    let truth: HashMap<u64, u64> = ground_truth.iter().copied().collect();
    let guess: HashMap<u64, u64> = predicted.iter().copied().collect();
    let right = human_ids
        .iter()
        .filter(|h| guess.get(h) == truth.get(h))
        .count();
    let truth_set: HashSet<(u64, u64)> = ground_truth.iter().copied().collect();
    let hits = predicted.iter().filter(|p| truth_set.contains(p)).count();
    let ratio = |num: usize, den: usize, empty: f64| {
        if den == 0 {
            empty
        } else {
            num as f64 / den as f64
        }
    };
    SceneScore {
        accuracy: ratio(right, human_ids.len(), 1.0),
        precision: ratio(
            hits,
            predicted.len(),
            if ground_truth.is_empty() { 1.0 } else { 0.0 },
        ),
        recall: ratio(hits, ground_truth.len(), 1.0),
    }
}

/// Mean and standard deviation of one metric over scenes.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Stat {
    pub mean: f64,
    /// Population standard deviation over scenes.
    pub std: f64,
}

/// Metrics averaged over the scenes of a data set.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Summary {
    pub scenes: usize,
    pub accuracy: Stat,
    pub precision: Stat,
    pub recall: Stat,
}

impl Summary {
    pub fn from_scores(scores: &[SceneScore]) -> Self {
        let stat = |f: fn(&SceneScore) -> f64| {
            let n = scores.len().max(1) as f64;
            let mean = scores.iter().map(f).sum::<f64>() / n;
            let var = scores.iter().map(|s| (f(s) - mean).powi(2)).sum::<f64>() / n;
            Stat {
                mean,
                std: var.sqrt(),
            }
        };
        Self {
            scenes: scores.len(),
            accuracy: stat(|s| s.accuracy),
            precision: stat(|s| s.precision),
            recall: stat(|s| s.recall),
        }
    }
}
