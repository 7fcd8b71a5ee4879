//! Whether a configuration can keep its answers fresh: a solve of
//! `[scene] capacity` objects per view must fit the freshness budget,
//! half of `[matcher] stale_after_ms`. An answer rests on snapshots that
//! may have waited for the solve in progress and then been solved
//! themselves; with each solve within half the bound, they are younger
//! than the bound when answered. A configuration over it is refused, by
//! `vref config check` and by the matcher alike, rather than served with
//! answers that would all be `stale`.
//!
//! The solve times are the slowest full solves measured on the reference
//! machine (the 2-core AMD EPYC virtual machine with AVX-512, one thread,
//! `vref bench solver` on rigid scenes, and the figures for the
//! exact tier at 128 and 256 objects), interpolated between sizes on
//! log-log axes and extended beyond the largest by its last slope.

use vref_match::{Method, Tier};

use crate::MatcherSettings;

/// Slowest full solve, (objects per view, milliseconds).
type Costs = &'static [(f64, f64)];

/// `sm`, `rrwm` and `paper` in the exact tier: every pair of edges, until
/// the method's tolerance; no kernel table above 64 objects.
const EXACT_SPATIAL: Costs = &[
    (8.0, 0.11),
    (16.0, 0.35),
    (32.0, 3.0),
    (64.0, 37.1),
    (128.0, 2400.0),
    (256.0, 31_000.0),
];
/// The same methods in the live tier (candidate pairs, early stop).
const LIVE_SPATIAL: Costs = &[
    (8.0, 0.04),
    (16.0, 0.12),
    (32.0, 0.67),
    (64.0, 3.6),
    (128.0, 19.0),
    (256.0, 120.0),
];
/// `rigid` (either tier: it has no iterations to cut short).
const RIGID: Costs = &[
    (8.0, 0.5),
    (32.0, 5.5),
    (64.0, 12.0),
    (128.0, 45.0),
    (256.0, 134.0),
];
/// `appearance`: the Hungarian assignment of the cosine table.
const APPEARANCE: Costs = &[(8.0, 0.01), (64.0, 0.5), (256.0, 10.0)];

fn costs(method: Method, tier: Tier) -> Costs {
    match (method, tier) {
        (Method::Rigid, _) => RIGID,
        (Method::Appearance, _) => APPEARANCE,
        (_, Tier::Exact) => EXACT_SPATIAL,
        (_, Tier::Live) => LIVE_SPATIAL,
    }
}

/// The slowest solve expected of `method` and `tier` at `objects` per
/// view on the reference machine, milliseconds.
pub fn estimated_solve_ms(method: Method, tier: Tier, objects: usize) -> f64 {
    interpolate(costs(method, tier), objects.max(1) as f64)
}

fn interpolate(points: Costs, n: f64) -> f64 {
    let segment = points
        .windows(2)
        .find(|w| n <= w[1].0)
        .or_else(|| points.windows(2).last());
    let Some(&[(n0, t0), (n1, t1)]) = segment else {
        return points.first().map_or(0.0, |p| p.1);
    };
    let slope = (t1 / t0).ln() / (n1 / n0).ln();
    t0 * (n / n0).powf(slope)
}

/// A configuration that cannot solve within its freshness budget.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "method `{method}` in the {tier} tier takes about {estimated_ms:.0} ms to solve {capacity} objects \
     per view on the reference machine, over the freshness budget of {budget_ms} ms (half of \
     stale_after_ms); lower [scene] capacity to {largest} or fewer, raise stale_after_ms to at \
     least {needed_ms}, or choose a faster method or tier"
)]
pub struct OverBudget {
    pub method: Method,
    pub tier: Tier,
    pub capacity: usize,
    pub estimated_ms: f64,
    pub budget_ms: u64,
    /// The largest capacity within the budget.
    pub largest: usize,
    /// The smallest stale_after_ms whose budget holds this capacity.
    pub needed_ms: u64,
}

/// The freshness budget of `settings`, milliseconds.
pub fn freshness_budget_ms(settings: &MatcherSettings) -> u64 {
    settings.stale_after_ms / 2
}

/// Refuses `settings` if a solve at `capacity` objects per view would not
/// fit its freshness budget. Settings whose method or tier do not parse
/// pass here: their own check names them.
pub fn check_budget(settings: &MatcherSettings, capacity: usize) -> Result<(), OverBudget> {
    let (Ok(method), Ok(tier)) = (settings.method(), settings.tier()) else {
        return Ok(());
    };
    let budget_ms = freshness_budget_ms(settings);
    let estimated_ms = estimated_solve_ms(method, tier, capacity);
    if estimated_ms <= budget_ms as f64 {
        return Ok(());
    }
    let fits = |n: usize| estimated_solve_ms(method, tier, n) <= budget_ms as f64;
    // Solve times grow with size: the largest that fits by bisection.
    let (mut lo, mut hi) = (0, capacity);
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        if fits(mid) { lo = mid } else { hi = mid - 1 }
    }
    Err(OverBudget {
        method,
        tier,
        capacity,
        estimated_ms,
        budget_ms,
        largest: lo,
        needed_ms: 2 * estimated_ms.ceil() as u64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings(method: &str, tier: &str) -> MatcherSettings {
        MatcherSettings {
            method: method.to_owned(),
            tier: tier.to_owned(),
            ..MatcherSettings::default()
        }
    }

    #[test]
    fn interpolation_passes_through_the_measured_points_and_grows() {
        assert!((estimated_solve_ms(Method::Paper, Tier::Exact, 64) - 37.1).abs() < 1e-9);
        let mut last = 0.0;
        for n in [1, 8, 20, 64, 100, 256, 1024] {
            let t = estimated_solve_ms(Method::Paper, Tier::Exact, n);
            assert!(t > last, "{n}: {t}");
            last = t;
        }
    }

    #[test]
    fn the_exact_tier_at_256_objects_is_refused_and_the_defaults_pass() {
        assert_eq!(check_budget(&MatcherSettings::default(), 256), Ok(()));
        assert_eq!(check_budget(&settings("paper", "live"), 256), Ok(()));
        assert_eq!(check_budget(&settings("paper", "exact"), 64), Ok(()));
        let over = check_budget(&settings("paper", "exact"), 256).unwrap_err();
        assert_eq!(over.budget_ms, 250);
        assert!(over.largest >= 64 && over.largest < 128, "{over}");
        assert!(fits_exactly(&over));
        let text = over.to_string();
        assert!(
            text.contains("[scene] capacity") && text.contains("stale_after_ms"),
            "{text}"
        );
        let slow = MatcherSettings {
            stale_after_ms: over.needed_ms,
            ..settings("paper", "exact")
        };
        assert_eq!(check_budget(&slow, 256), Ok(()));
    }

    fn fits_exactly(over: &OverBudget) -> bool {
        let t = |n| estimated_solve_ms(over.method, over.tier, n);
        t(over.largest) <= over.budget_ms as f64 && t(over.largest + 1) > over.budget_ms as f64
    }
}
