//! The four methods of ALGORITHMS.md, each producing a soft correspondence
//! that ends with Hungarian discretisation, vref's own `rigid`, and
//! `clipper`, an anchor from the robust-association literature.

mod appearance_only;
mod clipper;
mod paper;
mod rigid;
mod rrwm;
mod sm;
mod stability;
mod vector;

use std::fmt;
use std::str::FromStr;

pub use clipper::ClipperParams;
#[cfg(feature = "research")]
pub use rigid::assignment_under as rigid_assignment_under;
pub use rigid::{RigidMotion, RigidParams, median_spacing};
pub(crate) use rigid::{Track as RigidTrack, solve_from as rigid_solve_from};

use crate::{MatchError, Params, Problem, Solution, hungarian_max};

/// A matching method by its name in ALGORITHMS.md.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Appearance only (the paper's ATT baseline).
    Appearance,
    /// Spectral matching (Leordeanu & Hebert 2005).
    Sm,
    /// Reweighted random walks (Cho, Lee, Lee 2010).
    Rrwm,
    /// The paper's appearance-guided reweighted jumps.
    Paper,
    /// vref's own: a rigid motion between the views found by RANSAC,
    /// verification of every pair, "no partner" when nothing fits.
    Rigid,
    /// CLIPPER (Lusk, Fathian, How 2021): the densest consistent subgraph
    /// of appearance-gated candidate pairs.
    Clipper,
}

impl Method {
    pub const ALL: [Method; 6] = [
        Method::Appearance,
        Method::Sm,
        Method::Rrwm,
        Method::Paper,
        Method::Rigid,
        Method::Clipper,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Method::Appearance => "appearance",
            Method::Sm => "sm",
            Method::Rrwm => "rrwm",
            Method::Paper => "paper",
            Method::Rigid => "rigid",
            Method::Clipper => "clipper",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = MatchError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| MatchError::UnknownMethod(s.to_owned()))
    }
}

/// The soft result of a method before discretisation.
struct Soft {
    x: Vec<f64>,
    iterations: usize,
    converged: bool,
}

/// How a solve starts and when it may stop early, beyond the method's own
/// definition (which the default follows exactly).
#[derive(Debug, Clone, Copy, Default)]
pub struct SolveOptions<'a> {
    /// Initial correspondence, row-major `n x m` (e.g. the previous
    /// frame's soft answer); scaled to sum 1, ignored unless non-negative
    /// with a positive sum.
    pub warm_start: Option<&'a [f64]>,
    /// Stop once every row's best column has been unchanged for this many
    /// iterations.
    pub stop_when_stable: Option<usize>,
}

/// Runs `method` on `problem` and discretises its soft answer with the
/// Hungarian algorithm.
pub fn solve(method: Method, problem: &Problem, params: &Params) -> Result<Solution, MatchError> {
    solve_with(method, problem, params, SolveOptions::default())
}

/// [`solve`] with a warm start and an early stop.
pub fn solve_with(
    method: Method,
    problem: &Problem,
    params: &Params,
    options: SolveOptions<'_>,
) -> Result<Solution, MatchError> {
    params.validate()?;
    if let Some(w) = options.warm_start
        && w.len() != problem.len()
    {
        return Err(MatchError::WarmStartShape {
            len: w.len(),
            expected: problem.len(),
        });
    }
    let soft = match method {
        Method::Rigid => return Ok(rigid::solve(problem, params)),
        Method::Clipper => return Ok(clipper::solve(problem, params)),
        Method::Appearance => appearance_only::solve(problem),
        Method::Sm => sm::solve(problem, &params.sm, options),
        Method::Rrwm => rrwm::solve(problem, params, options),
        Method::Paper => paper::solve(problem, params, options),
    };
    let assignment = hungarian_max(&soft.x, problem.n, problem.m)?.row_to_col;
    let confidence = row_share_confidence(&soft.x, problem.m, &assignment);
    Ok(Solution {
        confidence,
        soft: soft.x,
        assignment,
        iterations: soft.iterations,
        converged: soft.converged,
        motion: None,
        margin: None,
        significance: None,
        fit: None,
        residuals: Vec::new(),
    })
}

/// The published methods' confidence: the assigned entry's share of its
/// row in the soft answer (negative entries count 0; a uniform row when
/// nothing is positive). A row left without a partner (more human than
/// robot objects) gets `1 -` the largest share: the chance that no column
/// is meant, as far as the soft answer tells.
fn row_share_confidence(soft: &[f64], m: usize, assignment: &[Option<usize>]) -> Vec<f64> {
    assignment
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let row = &soft[i * m..(i + 1) * m];
            let total: f64 = row.iter().map(|v| v.max(0.0)).sum();
            let share = |v: f64| {
                if total > 0.0 {
                    v.max(0.0) / total
                } else {
                    1.0 / m as f64
                }
            };
            match a {
                Some(j) => share(row[*j]),
                None => 1.0 - row.iter().map(|&v| share(v)).fold(0.0, f64::max),
            }
        })
        .collect()
}
