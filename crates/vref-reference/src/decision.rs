//! A finished solve as the matcher publishes it: the whole decision, for
//! viewers and headsets (vref_wire's decision service).

use vref_match::OkRule;
use vref_wire::{DecisionEntry, DecisionHeader};

use crate::answer::outcome;
use crate::solver::Solved;
use crate::stamp::micros;

/// The header of `solved`'s decision; `pair_count` is the publisher's.
pub fn decision_header(solved: &Solved, method: &str) -> DecisionHeader {
    let mut header = DecisionHeader {
        robot_session: solved.robot.session,
        robot_sequence: solved.robot.sequence,
        robot_timestamp_ns: solved.robot.timestamp_ns,
        human_session: solved.human.session,
        human_sequence: solved.human.sequence,
        human_timestamp_ns: solved.human.timestamp_ns,
        solved_ns: solved.finished.unix_ns,
        solve_us: micros(solved.took),
        solve_index: solved.solves,
        ..DecisionHeader::default()
    };
    if let Some(motion) = &solved.solution.motion {
        let r = &motion.rotation;
        for (k, slot) in header.rotation.iter_mut().enumerate() {
            *slot = r[(k / 3, k % 3)] as f32;
        }
        header.translation = motion.translation.map(|v| v as f32).into();
        header.flags |= DecisionHeader::FLAG_MOTION;
    }
    if let Some(median) = median(solved.solution.residuals.iter().flatten().copied()) {
        header.residual_median = median as f32;
        header.flags |= DecisionHeader::FLAG_RESIDUALS;
    }
    let bytes = method.as_bytes();
    let len = bytes.len().min(header.method.len());
    header.method[..len].copy_from_slice(&bytes[..len]);
    header
}

/// Human objects in `solved`'s decision: one entry each.
pub fn decision_len(solved: &Solved) -> usize {
    solved.human.graph.len()
}

/// The entry of human object `row`, with the status an answer about it
/// would have (before any staleness).
pub fn decision_entry(solved: &Solved, row: usize, rule: &OkRule) -> DecisionEntry {
    let solution = &solved.solution;
    let confidence = solution.confidence.get(row).copied().unwrap_or(0.0);
    let partner = solution.assignment.get(row).copied().flatten();
    let robot = solved.robot.graph.objects();
    let residual = partner.and(solution.residuals.get(row).copied().flatten());
    let mut flags = 0;
    if partner.is_some() {
        flags |= DecisionEntry::FLAG_PARTNER;
    }
    if residual.is_some() {
        flags |= DecisionEntry::FLAG_RESIDUAL;
    }
    DecisionEntry {
        human_track_id: solved.human.graph.objects().get(row).map_or(0, |o| o.id),
        robot_track_id: partner.and_then(|c| robot.get(c)).map_or(0, |o| o.id),
        confidence: confidence as f32,
        status: outcome(solution, row, confidence, rule) as u32,
        flags,
        residual: residual.map_or(0.0, |r| r as f32),
    }
}

/// The median of `values` (the mean of the middle two for an even count);
/// `None` when there are none.
fn median(values: impl Iterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let k = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[k]
    } else {
        0.5 * (v[k - 1] + v[k])
    })
}
