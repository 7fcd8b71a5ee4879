//! The four methods of ALGORITHMS.md. Each produces a soft correspondence
//! and ends with Hungarian discretisation.

mod appearance_only;
mod paper;
mod rrwm;
mod sm;
mod vector;

use std::fmt;
use std::str::FromStr;

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
}

impl Method {
    pub const ALL: [Method; 4] = [Method::Appearance, Method::Sm, Method::Rrwm, Method::Paper];

    pub fn name(self) -> &'static str {
        match self {
            Method::Appearance => "appearance",
            Method::Sm => "sm",
            Method::Rrwm => "rrwm",
            Method::Paper => "paper",
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

/// Runs `method` on `problem` and discretises its soft answer with the
/// Hungarian algorithm.
pub fn solve(method: Method, problem: &Problem, params: &Params) -> Result<Solution, MatchError> {
    params.validate()?;
    let soft = match method {
        Method::Appearance => appearance_only::solve(problem),
        Method::Sm => sm::solve(problem, &params.sm),
        Method::Rrwm => rrwm::solve(problem, params),
        Method::Paper => paper::solve(problem, params),
    };
    let assignment = hungarian_max(&soft.x, problem.n, problem.m)?.row_to_col;
    Ok(Solution {
        soft: soft.x,
        assignment,
        iterations: soft.iterations,
        converged: soft.converged,
    })
}
