//! Graph matching between the human view (rows) and the robot view
//! (columns), exactly as ../shared/ALGORITHMS.md defines it: appearance and
//! spatial affinities, Sinkhorn with slack, exact rectangular Hungarian, the
//! methods `appearance`, `sm`, `rrwm` and `paper`, vref's own `rigid`
//! (rigid verification, objects without a partner, calibrated confidence),
//! and the metrics.
//!
//! Pure computation: no IPC, no printing, no panics on input.
//!
//! A correspondence vector `x` is laid out row-major: entry `i * m + a`
//! pairs human object `i` with robot object `a` (`n` human, `m` robot
//! objects).

mod appearance;
mod calibration;
mod candidates;
#[cfg(target_arch = "x86_64")]
mod cpu;
mod distances;
mod edge_product;
pub mod engine;
mod error;
mod evaluation;
mod fast_exp;
mod fit;
mod hungarian;
mod methods;
mod metrics;
mod pair_kernel;
mod params;
mod problem;
mod sinkhorn;
mod solution;
mod spatial;
mod spatial_term;
mod tier;

pub use appearance::appearance_affinity;
// The experiments score calibration as `vref eval` does; nothing else
// needs the bin count.
#[cfg(feature = "research")]
pub use calibration::ECE_BINS;
pub use calibration::{Calibration, expected_calibration_error, logit};
pub use candidates::candidate_pairs;
pub use cpu::{UnknownSimd, check_simd_setting};
pub use distances::distance_matrix;
pub use error::MatchError;
pub use evaluation::{Evaluation, MethodReport, RowAnswer};
pub use fit::{OkRule, Verdict, pair_residuals, unseen_share};
pub use hungarian::{Hungarian, hungarian_max};
#[cfg(feature = "research")]
pub use methods::rigid_assignment_under;
pub use methods::{
    ClipperParams, Method, RigidMotion, RigidParams, SolveOptions, median_spacing, solve,
    solve_with,
};
pub use metrics::{SceneScore, Stat, Summary, score_scene};
pub use pair_kernel::PairAffinity;
pub use params::{LiveParams, PaperParams, Params, RrwmParams, SmParams};
pub use problem::{Problem, position_variance};
pub use sinkhorn::{Sinkhorn, sinkhorn_slack};
pub use solution::Solution;
pub use spatial::SpatialAffinity;
pub use spatial_term::SpatialTerm;
pub use tier::Tier;
