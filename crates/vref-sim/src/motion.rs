//! Where a live world's objects and headset are at time `t`, and when
//! objects are away: closed-form functions of `t`, so any process computes
//! the same state for any time without stepping through the ones before.

use std::f64::consts::{FRAC_1_SQRT_2, TAU};

use nalgebra::Vector3;
use rand::Rng;

use crate::dynamics::Dynamics;
use crate::random::{Purpose, keyed, uniform};

/// Periods of one object's motions stay within this factor of the mean.
const PERIOD_SPREAD: [f64; 2] = [0.75, 1.25];

/// One slow oscillation per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Sway<const N: usize> {
    period: [f64; N],
    phase: [f64; N],
}

impl<const N: usize> Sway<N> {
    pub(crate) fn draw<R: Rng>(mean_period: f64, rng: &mut R) -> Self {
        Self {
            period: [0; N].map(|_| mean_period * uniform(rng, PERIOD_SPREAD)),
            phase: [0; N].map(|_| TAU * rng.random::<f64>()),
        }
    }

    /// Per axis, `sin` of the phase at `t`, in [-1, 1].
    pub(crate) fn at(&self, t: f64) -> [f64; N] {
        let mut out = [0.0; N];
        for (o, (&p, &phase)) in out.iter_mut().zip(self.period.iter().zip(&self.phase)) {
            // The remainder is exact, so a large t (wall-clock seconds)
            // loses no precision in the angle.
            *o = (TAU * t.rem_euclid(p) / p + phase).sin();
        }
        out
    }
}

/// How one object moves and when it is away.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Motion {
    drift: Sway<2>,
    wobble: Sway<1>,
    /// Shifts this object's presence cycles against the others'.
    cycle_offset: f64,
    /// Keys this object's presence stream.
    object: u64,
}

/// One presence cycle: when in it the object is away, and how it is
/// turned once put back.
struct Cycle {
    index: i64,
    /// Start of the cycle, in world time.
    start: f64,
    /// Start of the absence, seconds into the cycle.
    away_from: f64,
    /// Yaw after the put-back.
    yaw: f64,
}

impl Motion {
    pub(crate) fn draw<R: Rng>(dynamics: &Dynamics, object: u64, rng: &mut R) -> Self {
        Self {
            drift: Sway::draw(dynamics.drift_period_s, rng),
            wobble: Sway::draw(dynamics.drift_period_s, rng),
            cycle_offset: dynamics.presence_period_s * rng.random::<f64>(),
            object,
        }
    }

    /// Displacement from the home place on the support surface; its length
    /// never exceeds the drift amplitude.
    pub(crate) fn drift(&self, dynamics: &Dynamics, t: f64) -> Vector3<f64> {
        let [x, y] = self.drift.at(t);
        let a = dynamics.drift_amplitude * FRAC_1_SQRT_2;
        Vector3::new(a * x, a * y, 0.0)
    }

    /// Yaw at `t`: the put-back's (or `home` if objects never leave) plus
    /// the wobble.
    pub(crate) fn yaw(&self, dynamics: &Dynamics, seed: u64, home: f64, t: f64) -> f64 {
        let [w] = self.wobble.at(t);
        let wobble = dynamics.wobble_deg.to_radians() * w;
        if dynamics.absent_share == 0.0 {
            return home + wobble;
        }
        let cycle = self.cycle(dynamics, seed, t);
        let put_back = if t - cycle.start >= cycle.away_from + absence(dynamics) {
            cycle
        } else {
            self.cycle_by_index(dynamics, seed, cycle.index.saturating_sub(1))
        };
        put_back.yaw + wobble
    }

    /// Whether the object is away at `t`.
    pub(crate) fn away(&self, dynamics: &Dynamics, seed: u64, t: f64) -> bool {
        self.away_during(dynamics, seed, t, t)
    }

    /// Whether the object is away at any time in `[from, to]`.
    pub(crate) fn away_during(&self, dynamics: &Dynamics, seed: u64, from: f64, to: f64) -> bool {
        let length = absence(dynamics);
        if length == 0.0 {
            return false;
        }
        let (first, last) = (
            self.cycle_index(dynamics, from),
            self.cycle_index(dynamics, to),
        );
        // A whole cycle in between holds a whole absence; this also bounds
        // the work for long spans.
        if last.saturating_sub(first) >= 2 {
            return true;
        }
        (first..=last).any(|index| {
            let cycle = self.cycle_by_index(dynamics, seed, index);
            let start = cycle.start + cycle.away_from;
            start <= to && from < start + length
        })
    }

    fn cycle_index(&self, dynamics: &Dynamics, t: f64) -> i64 {
        // Saturates for absurd times instead of wrapping.
        ((t + self.cycle_offset) / dynamics.presence_period_s).floor() as i64
    }

    fn cycle(&self, dynamics: &Dynamics, seed: u64, t: f64) -> Cycle {
        self.cycle_by_index(dynamics, seed, self.cycle_index(dynamics, t))
    }

    fn cycle_by_index(&self, dynamics: &Dynamics, seed: u64, index: i64) -> Cycle {
        let period = dynamics.presence_period_s;
        let mut rng = keyed(seed, Purpose::Presence, self.object, index as u64);
        let away_from = (period - absence(dynamics)) * rng.random::<f64>();
        let yaw = TAU * rng.random::<f64>();
        Cycle {
            index,
            start: index as f64 * period - self.cycle_offset,
            away_from,
            yaw,
        }
    }
}

/// How long each absence lasts.
fn absence(dynamics: &Dynamics) -> f64 {
    dynamics.absent_share * dynamics.presence_period_s
}
