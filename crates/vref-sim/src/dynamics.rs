//! How a live world changes over time: every knob of [`crate::LiveWorld`]
//! beyond the scene configuration. Lengths are metres, angles degrees,
//! times seconds.

use serde::{Deserialize, Serialize};

use crate::ConfigError;
use crate::config::{invalid, positive};

/// The motions of a live world and of the person pointing in it. Missing
/// fields take their defaults, unknown ones are refused.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Dynamics {
    /// Farthest an object wanders from its home place on the support
    /// surface. The layout keeps `2 * drift_amplitude` more clearance
    /// between objects and `drift_amplitude` more from the area's edge, so
    /// drifting objects never touch or leave the area.
    pub drift_amplitude: f64,
    /// Mean period of the drift; each object's two axes get their own
    /// periods within 25% of it, so paths are slow Lissajous figures.
    pub drift_period_s: f64,
    /// Amplitude of each object's slow turning about the vertical.
    pub wobble_deg: f64,
    /// Length of an object's presence cycle. Once per cycle, at a time
    /// drawn per object and cycle, the object is taken away for
    /// `absent_share` of the cycle, then put back at its home place turned
    /// at random. Objects' cycles are offset from each other.
    pub presence_period_s: f64,
    /// Share of time each object is away, in `[0, 1)`; 0 keeps every
    /// object in place for good.
    pub absent_share: f64,
    /// Farthest the headset moves from its place as the person's head
    /// sways (the robot's camera stands still).
    pub head_sway: f64,
    /// Mean period of the head sway.
    pub head_sway_period_s: f64,
    /// How long the person points at one object before choosing another.
    pub gesture_period_s: f64,
    /// Standard deviation, per axis across the ray, of the pointing
    /// direction's error; one error per gesture.
    pub pointing_noise_deg: f64,
    /// Cone half-angle the gesture recogniser reports with each ray.
    pub cone_half_angle_deg: f64,
    /// Confidence the gesture recogniser reports with each ray.
    pub gesture_confidence: f64,
    /// Where the pointing hand is relative to the headset: right, down
    /// (vertical) and forward (horizontal, the way the person faces).
    pub hand_offset: [f64; 3],
}

impl Default for Dynamics {
    fn default() -> Self {
        Self {
            drift_amplitude: 0.01,
            drift_period_s: 20.0,
            wobble_deg: 8.0,
            presence_period_s: 60.0,
            absent_share: 0.15,
            head_sway: 0.02,
            head_sway_period_s: 6.0,
            gesture_period_s: 5.0,
            pointing_noise_deg: 2.0,
            cone_half_angle_deg: 10.0,
            gesture_confidence: 0.9,
            hand_offset: [0.15, 0.3, 0.35],
        }
    }
}

impl Dynamics {
    /// A world that stands still: no drift, turning, absences or sway.
    pub fn still() -> Self {
        Self {
            drift_amplitude: 0.0,
            wobble_deg: 0.0,
            absent_share: 0.0,
            head_sway: 0.0,
            ..Self::default()
        }
    }

    /// Refuses values a live world is not defined for, naming the field
    /// as `dynamics.<name>`.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (name, value) in [
            ("drift_amplitude", self.drift_amplitude),
            ("wobble_deg", self.wobble_deg),
            ("head_sway", self.head_sway),
            ("pointing_noise_deg", self.pointing_noise_deg),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(invalid(
                    &format!("dynamics.{name}"),
                    format!("{value} must be finite and >= 0"),
                ));
            }
        }
        for (name, value) in [
            ("drift_period_s", self.drift_period_s),
            ("presence_period_s", self.presence_period_s),
            ("head_sway_period_s", self.head_sway_period_s),
            ("gesture_period_s", self.gesture_period_s),
        ] {
            positive(&format!("dynamics.{name}"), value)?;
        }
        if !(0.0..1.0).contains(&self.absent_share) {
            return Err(invalid(
                "dynamics.absent_share",
                format!("{} must lie in [0, 1)", self.absent_share),
            ));
        }
        let cone = self.cone_half_angle_deg;
        if !(cone > 0.0 && cone <= 90.0) {
            return Err(invalid(
                "dynamics.cone_half_angle_deg",
                format!("{cone} must lie in (0, 90]"),
            ));
        }
        if !(0.0..=1.0).contains(&self.gesture_confidence) {
            return Err(invalid(
                "dynamics.gesture_confidence",
                format!("{} must lie in [0, 1]", self.gesture_confidence),
            ));
        }
        if let Some(value) = self.hand_offset.iter().find(|v| !v.is_finite()) {
            return Err(invalid(
                "dynamics.hand_offset",
                format!("{value} is not a finite number"),
            ));
        }
        Ok(())
    }
}
