//! The timing loop of `vref bench solver`: solves of vref-sim's rigid
//! scenes of an exact size, through the matcher's engine, summed up as
//! percentiles. Nothing here asserts a duration.

use std::time::Instant;

use anyhow::ensure;
use vref_match::engine::Engine;
use vref_match::{Method, Params, Tier};
use vref_scene::Side;
use vref_sim::RigidScene;

/// Distinct scenes cycled through by the repeats, so that one lucky scene
/// does not decide the figures.
const DISTINCT_SCENES: usize = 8;

/// What is timed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Affinities, solve and Hungarian of a new scene.
    Full,
    /// The engine's update and solve after one human object of a solved
    /// scene moved.
    Incremental,
}

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Full => "full",
            Mode::Incremental => "incremental",
        }
    }
}

/// The synthetic scenes a benchmark times: `objects` per view, from
/// `seed`, the robot view's positions off by `noise` (standard deviation
/// per axis, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scenes {
    pub objects: usize,
    pub seed: u64,
    pub noise: f64,
    /// Whether both views carry their up vectors ([`RigidScene::upright`]).
    pub up: bool,
}

/// Percentiles of one method, size and mode.
#[derive(Debug, Clone, PartialEq)]
pub struct Timing {
    pub method: Method,
    pub tier: Tier,
    pub objects: usize,
    /// The robot view's position noise, metres.
    pub noise: f64,
    pub mode: Mode,
    pub median_us: f64,
    pub p99_us: f64,
    /// Median iteration count of the method's main loop.
    pub iterations: usize,
}

/// Times `repeats` solves of `method` in `tier` on `objects`-object scenes,
/// through the matcher's [`Engine`]: a full solve is a new engine given
/// both views; an incremental one is the update of the moved view and the
/// solve of an engine that had solved the scene before (not timed).
pub fn time_solver(
    method: Method,
    tier: Tier,
    spec: Scenes,
    mode: Mode,
    params: &Params,
    repeats: usize,
) -> anyhow::Result<Timing> {
    ensure!(repeats > 0, "a benchmark needs at least 1 repeat");
    let Scenes {
        objects,
        seed,
        noise,
        up,
    } = spec;
    let scenes = (0..DISTINCT_SCENES.min(repeats))
        .map(|s| {
            let scene = RigidScene::with_noise(objects, seed.wrapping_add(s as u64), noise)?;
            if up { scene.upright() } else { Ok(scene) }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut micros = Vec::with_capacity(repeats);
    let mut iterations = Vec::with_capacity(repeats);
    for r in 0..repeats {
        let base = &scenes[r % scenes.len()];
        let mut engine = Engine::new(method, tier, *params)?;
        let timed = match mode {
            Mode::Full => {
                let start = Instant::now();
                engine.update(Side::Human, &base.human)?;
                engine.update(Side::Robot, &base.robot)?;
                let iterations = engine.solve()?.0.iterations;
                (start.elapsed(), iterations)
            }
            Mode::Incremental => {
                let moved = base.moved(r, seed.wrapping_mul(31).wrapping_add(r as u64))?;
                engine.update(Side::Human, &base.human)?;
                engine.update(Side::Robot, &base.robot)?;
                engine.solve()?;
                let start = Instant::now();
                engine.update(Side::Human, &moved.human)?;
                let iterations = engine.solve()?.0.iterations;
                (start.elapsed(), iterations)
            }
        };
        micros.push(timed.0.as_secs_f64() * 1e6);
        iterations.push(timed.1);
    }
    micros.sort_by(f64::total_cmp);
    iterations.sort_unstable();
    Ok(Timing {
        method,
        tier,
        objects,
        noise,
        mode,
        median_us: percentile(&micros, 0.5),
        p99_us: percentile(&micros, 0.99),
        iterations: iterations[iterations.len() / 2],
    })
}

/// Nearest-rank percentile (vref_measure's one definition) of sorted,
/// non-empty `values`; 0 for none.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    vref_measure::percentile(sorted, q).unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    fn scenes(objects: usize, seed: u64) -> Scenes {
        Scenes {
            objects,
            seed,
            noise: RigidScene::POSITION_NOISE,
            up: false,
        }
    }

    #[test]
    fn timing_reports_percentiles_and_refuses_bad_input() {
        for tier in Tier::ALL {
            let t = time_solver(
                Method::Sm,
                tier,
                scenes(6, 1),
                Mode::Incremental,
                &Params::default(),
                3,
            )
            .unwrap();
            assert!(t.median_us > 0.0 && t.p99_us >= t.median_us);
            assert!(t.iterations > 0);
            assert_eq!(t.tier, tier);
        }
        let none = time_solver(
            Method::Sm,
            Tier::Exact,
            scenes(6, 1),
            Mode::Full,
            &Params::default(),
            0,
        );
        assert_eq!(
            none.unwrap_err().to_string(),
            "a benchmark needs at least 1 repeat"
        );
    }

    #[test]
    fn percentile_is_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 0.5), 50.0);
        assert_eq!(percentile(&v, 0.99), 99.0);
        assert_eq!(percentile(&[7.0], 0.99), 7.0);
    }
}
