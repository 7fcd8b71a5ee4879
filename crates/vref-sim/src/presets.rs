//! The two scene families of the paper's evaluation, rebuilt from physical
//! quantities (the paper's own data are not available).
//!
//! - `moi`: a cleared part of a table, 0.55 x 0.4 m, seen from 0.7-1.1 m
//!   and from above (30-60 degrees down) by the robot's head camera and by
//!   a person standing across or beside the table. Seven classes, about
//!   ten objects a hand's width apart, look-alike instances (2-4 apples,
//!   1-3 oranges, 1-3 cans); the mug, the can and the cereal box look
//!   different from each side. Depth error of a few centimetres is large
//!   against distances of 10-30 cm.
//! - `mrc`: a 3 x 2.2 m patch of workshop floor seen from 2.5-4.5 m by a
//!   mobile robot's camera and a standing person. Six to ten identical
//!   cartons and a few other things; at that range depth error deforms
//!   distances by decimetres.
//!
//! The robot carries an Intel RealSense D435-like RGB-D camera (69 x 42
//! degrees, depth RMS error under 2% at 2 m), the person a HoloLens 2-like
//! headset (photo camera 65 x 38 degrees; depth from its long-throw
//! sensor at room scale, from its short-range sensor and spatial map at
//! arm's length, which places small objects less precisely).

use std::fmt;
use std::str::FromStr;

use crate::ConfigError;
use crate::config::{
    CameraSpec, ClassSpec, EdgeFamily, FeatureSpec, LightingSpec, Look, Patch, SensorNoise,
    SimConfig, ViewpointSpec, WorkspaceSpec,
};
use crate::shape::Shape;

/// A named, complete configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preset {
    Moi,
    Mrc,
}

impl Preset {
    pub const ALL: [Preset; 2] = [Preset::Moi, Preset::Mrc];

    pub fn name(self) -> &'static str {
        match self {
            Preset::Moi => "moi",
            Preset::Mrc => "mrc",
        }
    }

    pub fn config(self) -> SimConfig {
        match self {
            Preset::Moi => moi(),
            Preset::Mrc => mrc(),
        }
    }
}

impl fmt::Display for Preset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Preset {
    type Err = ConfigError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Preset::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| ConfigError::UnknownPreset(s.to_owned()))
    }
}

fn look(patches: &[([f64; 3], f64)], edges: &[(f64, f64)]) -> Look {
    Look {
        patches: patches
            .iter()
            .map(|&(rgb, area)| Patch { rgb, area })
            .collect(),
        edges: edges
            .iter()
            .map(|&(angle_deg, strength)| EdgeFamily {
                angle_deg,
                strength,
            })
            .collect(),
    }
}

/// Texture without a dominant direction.
const ISOTROPIC: [(f64, f64); 4] = [(0.0, 1.0), (45.0, 1.0), (90.0, 1.0), (135.0, 1.0)];

fn scaled(edges: &[(f64, f64)], by: f64) -> Vec<(f64, f64)> {
    edges.iter().map(|&(a, s)| (a, s * by)).collect()
}

const WHITE: [f64; 3] = [0.8, 0.8, 0.78];

/// RealSense D435-like, on the robot.
fn robot_camera() -> CameraSpec {
    CameraSpec {
        distance: [0.0, 0.0],
        height: [0.0, 0.0],
        aim_jitter: 0.05,
        roll_deg: 1.0,
        hfov_deg: 69.0,
        vfov_deg: 42.0,
        image_width: 1280,
        depth_range: [0.3, 8.0],
        min_visible_fraction: 0.35,
        min_pixels: 300.0,
        colour_gain: [1.0, 1.0, 1.0],
        noise: SensorNoise {
            // D435: depth RMS error under 2% at 2 m, i.e. k = 0.04 / 2^2.
            depth: 0.01,
            depth_scale: 0.005,
            surface_bias: 1.0,
            segmentation: 0.15,
            pixel: 4.0,
            white_balance: 0.05,
            exposure: 0.15,
        },
    }
}

/// HoloLens 2-like, on the person's head, with its long-range depth.
fn human_camera() -> CameraSpec {
    CameraSpec {
        distance: [0.0, 0.0],
        height: [0.0, 0.0],
        aim_jitter: 0.08,
        roll_deg: 6.0,
        hfov_deg: 64.7,
        vfov_deg: 38.3,
        image_width: 1280,
        depth_range: [0.3, 6.0],
        min_visible_fraction: 0.35,
        min_pixels: 300.0,
        colour_gain: [1.05, 1.0, 0.9],
        noise: SensorNoise {
            // Long-throw depth mode: about 15 cm at 3.5 m.
            depth: 0.012,
            depth_scale: 0.01,
            surface_bias: 1.0,
            segmentation: 0.2,
            pixel: 4.0,
            white_balance: 0.08,
            exposure: 0.2,
        },
    }
}

fn features() -> FeatureSpec {
    FeatureSpec {
        hue_bins: 12,
        value_levels: 3,
        grey_bins: 4,
        orientation_bins: 8,
        colour_weight: 1.0,
        gradient_weight: 0.6,
        outline_strength: 0.5,
    }
}

/// Table top, small objects close together.
pub fn moi() -> SimConfig {
    const RED: [f64; 3] = [0.55, 0.05, 0.04];
    const CAN_RED: [f64; 3] = [0.6, 0.03, 0.05];
    const ORANGE: [f64; 3] = [0.85, 0.33, 0.03];
    const BLUE: [f64; 3] = [0.08, 0.18, 0.55];
    const YELLOW: [f64; 3] = [0.82, 0.65, 0.08];
    const INK: [f64; 3] = [0.04, 0.04, 0.05];
    let can_print = scaled(&ISOTROPIC, 0.35);
    let classes = vec![
        ClassSpec {
            name: "apple".into(),
            shape: Shape::Sphere { radius: 0.038 },
            size_variation: 0.06,
            instances: [2, 4],
            instance_variation: 0.05,
            sides: vec![look(
                &[(RED, 0.8), ([0.5, 0.42, 0.08], 0.2)],
                &scaled(&ISOTROPIC, 0.05),
            )],
            top: look(
                &[(RED, 0.7), ([0.25, 0.15, 0.05], 0.3)],
                &scaled(&ISOTROPIC, 0.1),
            ),
        },
        ClassSpec {
            name: "orange".into(),
            shape: Shape::Sphere { radius: 0.036 },
            size_variation: 0.06,
            instances: [1, 3],
            instance_variation: 0.04,
            sides: vec![look(&[(ORANGE, 1.0)], &scaled(&ISOTROPIC, 0.12))],
            top: look(
                &[(ORANGE, 0.9), ([0.2, 0.3, 0.05], 0.1)],
                &scaled(&ISOTROPIC, 0.15),
            ),
        },
        ClassSpec {
            name: "lemon".into(),
            shape: Shape::Sphere { radius: 0.03 },
            size_variation: 0.06,
            instances: [0, 2],
            instance_variation: 0.04,
            sides: vec![look(&[(YELLOW, 1.0)], &scaled(&ISOTROPIC, 0.08))],
            top: look(&[(YELLOW, 1.0)], &scaled(&ISOTROPIC, 0.08)),
        },
        ClassSpec {
            name: "soda can".into(),
            shape: Shape::Cylinder {
                radius: 0.033,
                height: 0.122,
            },
            size_variation: 0.0,
            instances: [1, 3],
            instance_variation: 0.02,
            // Logo on the front, nutrition table on the back.
            sides: vec![
                look(&[(CAN_RED, 0.65), (WHITE, 0.35)], &can_print),
                look(&[(CAN_RED, 0.9), (WHITE, 0.1)], &[(0.0, 0.3)]),
                look(&[(CAN_RED, 0.7), (WHITE, 0.3)], &[(0.0, 0.6), (90.0, 0.4)]),
                look(&[(CAN_RED, 0.9), (WHITE, 0.1)], &[(0.0, 0.3)]),
            ],
            top: look(&[([0.6, 0.6, 0.62], 1.0)], &scaled(&ISOTROPIC, 0.2)),
        },
        ClassSpec {
            name: "mug".into(),
            shape: Shape::Cylinder {
                radius: 0.042,
                height: 0.095,
            },
            size_variation: 0.03,
            instances: [0, 2],
            instance_variation: 0.03,
            // Black print on the front, handle on the left.
            sides: vec![
                look(&[(WHITE, 0.7), (INK, 0.3)], &scaled(&ISOTROPIC, 0.4)),
                look(&[(WHITE, 1.0)], &[(90.0, 0.6), (0.0, 0.2)]),
                look(&[(WHITE, 1.0)], &[(0.0, 0.05)]),
                look(&[(WHITE, 1.0)], &[(0.0, 0.05)]),
            ],
            top: look(
                &[([0.15, 0.12, 0.1], 0.6), (WHITE, 0.4)],
                &scaled(&ISOTROPIC, 0.3),
            ),
        },
        ClassSpec {
            name: "cereal box".into(),
            shape: Shape::Cuboid {
                size: [0.07, 0.19, 0.27],
            },
            size_variation: 0.0,
            instances: [0, 1],
            instance_variation: 0.02,
            // Blue carton, print all round: the front busy, the narrow
            // sides banded, the back half white.
            sides: vec![
                look(
                    &[(BLUE, 0.5), (WHITE, 0.3), (YELLOW, 0.2)],
                    &scaled(&ISOTROPIC, 0.5),
                ),
                look(&[(BLUE, 0.6), (WHITE, 0.4)], &[(0.0, 0.5)]),
                look(&[(WHITE, 0.5), (BLUE, 0.5)], &[(0.0, 0.4), (90.0, 0.4)]),
                look(&[(BLUE, 0.6), (WHITE, 0.4)], &[(0.0, 0.5)]),
            ],
            top: look(&[(BLUE, 1.0)], &[(0.0, 0.1)]),
        },
        ClassSpec {
            name: "water bottle".into(),
            shape: Shape::Cylinder {
                radius: 0.034,
                height: 0.21,
            },
            size_variation: 0.0,
            instances: [0, 2],
            instance_variation: 0.02,
            sides: vec![look(
                // Clear blue plastic, a green label.
                &[([0.35, 0.5, 0.6], 0.6), ([0.1, 0.45, 0.2], 0.4)],
                &[(90.0, 0.3), (0.0, 0.2)],
            )],
            top: look(
                &[([0.1, 0.45, 0.2], 0.5), ([0.35, 0.5, 0.6], 0.5)],
                &scaled(&ISOTROPIC, 0.1),
            ),
        },
    ];
    SimConfig {
        workspace: WorkspaceSpec {
            // A cleared part of a table: objects a hand's width apart.
            area: [0.55, 0.4],
            min_gap: 0.01,
            placement_attempts: 200,
            surface: look(&[([0.55, 0.4, 0.25], 1.0)], &[(0.0, 0.15)]),
        },
        classes,
        viewpoints: ViewpointSpec {
            robot_azimuth_deg: [0.0, 360.0],
            human_offset_deg: [110.0, 250.0],
        },
        robot: CameraSpec {
            distance: [0.55, 0.8],
            height: [0.45, 0.65],
            ..robot_camera()
        },
        human: CameraSpec {
            distance: [0.45, 0.75],
            height: [0.55, 0.8],
            // At arm's length the headset's depth comes from its short-range
            // (hand-tracking) mode and spatial map, which resolve a fist-sized
            // object only to a few centimetres: about 5 cm at 0.85 m.
            noise: SensorNoise {
                depth: 0.07,
                ..human_camera().noise
            },
            ..human_camera()
        },
        lighting: LightingSpec {
            ambient: 0.45,
            elevation_deg: [35.0, 80.0],
        },
        features: features(),
        min_objects_per_view: 3,
        attempts: 50,
    }
}

/// Workshop floor, objects 3-5 m from both cameras, most of them identical.
pub fn mrc() -> SimConfig {
    const CARDBOARD: [f64; 3] = [0.45, 0.3, 0.15];
    let tape = [(0.0, 0.25)];
    let classes = vec![
        ClassSpec {
            name: "carton".into(),
            shape: Shape::Cuboid {
                size: [0.4, 0.3, 0.3],
            },
            size_variation: 0.0,
            instances: [6, 10],
            instance_variation: 0.04,
            // A white shipping label on the front face only.
            sides: vec![
                look(
                    &[(CARDBOARD, 0.85), (WHITE, 0.15)],
                    &[(0.0, 0.4), (90.0, 0.2)],
                ),
                look(&[(CARDBOARD, 1.0)], &tape),
                look(&[(CARDBOARD, 1.0)], &tape),
                look(&[(CARDBOARD, 1.0)], &tape),
            ],
            top: look(&[(CARDBOARD, 0.9), ([0.55, 0.45, 0.3], 0.1)], &[(0.0, 0.5)]),
        },
        ClassSpec {
            name: "crate".into(),
            shape: Shape::Cuboid {
                size: [0.55, 0.37, 0.3],
            },
            size_variation: 0.0,
            instances: [0, 2],
            instance_variation: 0.03,
            sides: vec![look(
                &[([0.12, 0.2, 0.35], 1.0)],
                &[(0.0, 0.5), (90.0, 0.5)],
            )],
            top: look(
                &[([0.12, 0.2, 0.35], 0.6), ([0.05; 3], 0.4)],
                &[(0.0, 0.6), (90.0, 0.6)],
            ),
        },
        ClassSpec {
            name: "traffic cone".into(),
            shape: Shape::Cylinder {
                radius: 0.14,
                height: 0.5,
            },
            size_variation: 0.0,
            instances: [0, 2],
            instance_variation: 0.03,
            sides: vec![look(
                &[([0.9, 0.3, 0.02], 0.8), (WHITE, 0.2)],
                &[(0.0, 0.4), (90.0, 0.1)],
            )],
            top: look(&[([0.9, 0.3, 0.02], 1.0)], &scaled(&ISOTROPIC, 0.1)),
        },
        ClassSpec {
            name: "barrel".into(),
            shape: Shape::Cylinder {
                radius: 0.28,
                height: 0.88,
            },
            size_variation: 0.0,
            instances: [0, 1],
            instance_variation: 0.03,
            sides: vec![look(&[([0.05, 0.15, 0.5], 1.0)], &[(0.0, 0.3)])],
            top: look(&[([0.05, 0.15, 0.5], 1.0)], &scaled(&ISOTROPIC, 0.2)),
        },
        ClassSpec {
            name: "ball".into(),
            shape: Shape::Sphere { radius: 0.11 },
            size_variation: 0.0,
            instances: [0, 1],
            instance_variation: 0.03,
            sides: vec![look(&[([0.1, 0.5, 0.1], 1.0)], &scaled(&ISOTROPIC, 0.05))],
            top: look(&[([0.1, 0.5, 0.1], 1.0)], &scaled(&ISOTROPIC, 0.05)),
        },
    ];
    SimConfig {
        workspace: WorkspaceSpec {
            area: [3.0, 2.2],
            min_gap: 0.05,
            placement_attempts: 200,
            surface: look(&[([0.35, 0.35, 0.33], 1.0)], &scaled(&ISOTROPIC, 0.05)),
        },
        classes,
        viewpoints: ViewpointSpec {
            robot_azimuth_deg: [0.0, 360.0],
            human_offset_deg: [90.0, 270.0],
        },
        robot: CameraSpec {
            distance: [3.0, 4.5],
            height: [0.8, 1.2],
            aim_jitter: 0.2,
            ..robot_camera()
        },
        human: CameraSpec {
            distance: [2.5, 4.0],
            height: [1.5, 1.8],
            aim_jitter: 0.3,
            ..human_camera()
        },
        lighting: LightingSpec {
            ambient: 0.5,
            elevation_deg: [50.0, 85.0],
        },
        features: features(),
        min_objects_per_view: 3,
        attempts: 50,
    }
}
