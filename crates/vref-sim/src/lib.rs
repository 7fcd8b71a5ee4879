//! Synthetic two-view scenes: one workspace seen by the robot's RGB-D
//! camera and by the person's AR headset, generated from physical causes
//! rather than by perturbing a copy.
//!
//! A scene is built in this order, each step from the one before:
//!
//! 1. **World.** Objects of configured classes stand on the support plane
//!    (z = 0) at random places without overlap; instances of a class share
//!    a look up to a small per-instance tint, and a class may look
//!    different from each side (print on the front, a handle on the left).
//! 2. **Cameras.** Both cameras get a pose around the workspace (the
//!    headset from another side than the robot), a field of view and a
//!    depth range; a main light shades the surfaces.
//! 3. **Visibility.** Each object's surface samples count as seen by a
//!    camera if they face it, fall in its image and depth range, and no
//!    other object lies in between. Objects with too small a seen share or
//!    too few pixels are not detected, so each view lacks some objects.
//! 4. **Measurement.** A camera's segmentation mask of an object is its
//!    seen surface with one side of the outline cut off or bled into the
//!    surface behind; the reported position is the mask's depth centroid in
//!    the camera frame (x right, y down, z forward), which lies on the
//!    visible front, not at the object's centre, and is moved along its ray
//!    by a depth error of standard deviation `k z^2` (and scaled by a
//!    per-frame depth scale error). The feature is the colour and
//!    gradient-orientation histogram of the masked pixels as this camera's
//!    colour response, white balance and exposure render them under the
//!    scene's light, with pixel-count sampling noise. Every error of this
//!    step is a knob of [`SensorNoise`]; [`SimConfig::noiseless`] turns
//!    them all off, leaving only what viewpoint, light and occlusion do.
//! 5. **Graphs.** Each view lists its objects under random track ids,
//!    sorted by id; the ground truth pairs exactly the objects both views
//!    detected.
//!
//! [`RigidScene`]s are simpler: exactly `n` objects, all seen by both
//! views, the robot's a rigid motion of the human's plus noise; they are
//! what `vref bench solver` times.
//!
//! [`Sweep`] runs the matchers of `vref-match` over scenes generated with
//! one family of noise knobs scaled ([`NoiseSweep`]): accuracy against
//! noise.
//!
//! Everything is a function of the configuration, the seed and the scene
//! index (one ChaCha8 stream per scene, no hash-map iteration), so files
//! are reproducible byte for byte. Across platforms they may differ in the
//! last digits, where the system's `ln`, `sin` and `cos` round differently.
//!
//! A [`LiveWorld`] is the same workspace over time, for the live feeds:
//! laid out and seen as above, its objects then drift, turn, leave and
//! come back as closed-form functions of time ([`Dynamics`]), and a person
//! points at them ([`Gesture`]). It too is a pure function of its inputs
//! and the time, so separate processes agree on it without talking.

mod appearance;
mod camera;
mod config;
mod dynamics;
mod error;
mod generator;
mod live;
mod measurement;
mod motion;
mod presets;
mod random;
mod rigid_scene;
mod sensor;
mod shape;
mod staging;
mod sweep;
pub mod unrelated;
mod visibility;
mod world;

pub use camera::Camera;
pub use config::{
    CameraSpec, ClassSpec, EdgeFamily, FeatureSpec, LightingSpec, Look, Patch, SensorNoise,
    SimConfig, ViewpointSpec, WorkspaceSpec,
};
pub use dynamics::Dynamics;
pub use error::{ConfigError, RigidSceneError, SceneError, SweepError};
pub use generator::{GeneratedScene, Generator, Sighting, View};
pub use live::{Gesture, LiveObject, LiveView, LiveWorld};
pub use presets::{Preset, moi, mrc};
pub use rigid_scene::RigidScene;
pub use shape::Shape;
pub use sweep::{DEFAULT_LEVELS, NoiseSweep, Sweep, SweepPoint, accuracy_curves};
pub use world::WorldObject;
