//! The live synthetic world as a feed: snapshots of one camera at the
//! snapshot rate and, for the gesture feed, the person's pointing at the
//! gesture rate, both on ticks aligned to the epoch so that the two feed
//! processes see one world.

use vref_config::FeedSettings;
use vref_scene::Side;
use vref_sim::{Dynamics, LiveWorld, Preset, SimConfig};
use vref_wire::ObjectEntry;

use crate::entries::view_entries;
use crate::ticks::Ticker;
use crate::{Due, Publication, Ray, RunError, SetupError, Target};

/// The live world of the `[feeds]` settings with `objects` objects: what
/// both feeds publish and what a checker of their answers must compute.
/// More objects than the preset ever draws get a larger workspace
/// ([`with_room_for`]).
pub fn synthetic_world(
    feeds: &FeedSettings,
    objects: Option<usize>,
) -> Result<(Preset, LiveWorld), SetupError> {
    let preset: Preset = feeds.preset.parse().map_err(SetupError::Preset)?;
    let config = with_room_for(preset.config(), objects);
    let world = LiveWorld::new(config, Dynamics::default(), feeds.seed, objects)
        .map_err(SetupError::World)?;
    Ok((preset, world))
}

/// The preset's world scaled up for `objects` when that is more than its
/// classes ever draw together (a table top holds about ten objects, not
/// 64): the workspace, the cameras' distance, height and aim, and their
/// far depth limit grow by sqrt(objects / mean drawn count), so objects
/// stand as densely as in the preset and both cameras see the workspace
/// under the same angles. Benchmarks at 32 to 128 objects need this; up
/// to the preset's own maximum the world is the preset's.
pub(crate) fn with_room_for(mut config: SimConfig, objects: Option<usize>) -> SimConfig {
    let Some(n) = objects else {
        return config;
    };
    let most: usize = config.classes.iter().map(|c| c.instances[1]).sum();
    if n <= most {
        return config;
    }
    let mean: f64 = config
        .classes
        .iter()
        .map(|c| (c.instances[0] + c.instances[1]) as f64 / 2.0)
        .sum();
    let k = (n as f64 / mean.max(1.0)).sqrt();
    config.workspace.area = config.workspace.area.map(|a| a * k);
    for camera in [&mut config.robot, &mut config.human] {
        camera.distance = camera.distance.map(|d| d * k);
        camera.height = camera.height.map(|h| h * k);
        camera.aim_jitter *= k;
        camera.depth_range[1] *= k;
    }
    config
}

#[derive(Debug)]
pub(crate) struct Synthetic {
    world: LiveWorld,
    side: Side,
    snapshots: Ticker,
    gestures: Option<Ticker>,
    feature_dim: usize,
    /// Whether snapshots carry the camera's up vector.
    up_vectors: bool,
    /// Reused for every frame.
    entries: Vec<ObjectEntry>,
}

impl Synthetic {
    pub(crate) fn new(
        world: LiveWorld,
        side: Side,
        epoch_ns: u64,
        rate_hz: f64,
        gesture_rate_hz: Option<f64>,
    ) -> Self {
        let feature_dim = world.config().features.dim();
        let entries = Vec::with_capacity(world.object_count());
        Self {
            world,
            side,
            snapshots: Ticker::new(epoch_ns, rate_hz),
            gestures: gesture_rate_hz.map(|rate| Ticker::new(epoch_ns, rate)),
            feature_dim,
            up_vectors: false,
            entries,
        }
    }

    /// Snapshots carry their camera's up vector: the world's vertical in
    /// the camera frame at the snapshot's moment.
    pub(crate) fn with_up_vectors(mut self, up_vectors: bool) -> Self {
        self.up_vectors = up_vectors;
        self
    }

    pub(crate) fn next(&mut self, now_ns: u64) -> Result<Due<'_>, RunError> {
        // Both counts start now, so that a tick that loses a tie to the
        // other stream is still due next time.
        self.snapshots.start(now_ns);
        if let Some(gestures) = &mut self.gestures {
            gestures.start(now_ns);
        }
        loop {
            let snapshot = self.snapshots.peek(now_ns);
            if let Some(gestures) = &mut self.gestures {
                let tick = gestures.peek(now_ns);
                if tick.at_ns <= snapshot.at_ns {
                    gestures.take(tick);
                    // No gesture while nothing stays for the whole slot.
                    if let Some(g) = self.world.gesture(tick.t) {
                        let ray = Ray {
                            origin: g.origin.coords.map(|v| v as f32).into(),
                            direction: g.direction.map(|v| v as f32).into(),
                            cone_half_angle: g.cone_half_angle as f32,
                            confidence: g.confidence as f32,
                        };
                        let target = Target {
                            slot: g.slot,
                            human_id: g.human_id,
                            robot_id: g.robot_id,
                        };
                        return Ok(Due {
                            at_ns: tick.at_ns,
                            publication: Publication::Gesture {
                                ray,
                                target: Some(target),
                            },
                        });
                    }
                    continue;
                }
            }
            self.snapshots.take(snapshot);
            // Tick numbers key the measurement errors: the same frame
            // measures the same way in any process.
            let view = self
                .world
                .observe(self.side, snapshot.t, snapshot.index as u64);
            view_entries(&view, &mut self.entries)?;
            let up = self.up_vectors.then(|| {
                let up = view.camera.direction_to_camera(&nalgebra::Vector3::z());
                [up.x as f32, up.y as f32, up.z as f32]
            });
            return Ok(Due {
                at_ns: snapshot.at_ns,
                publication: Publication::Snapshot {
                    feature_dim: self.feature_dim,
                    entries: &self.entries,
                    up,
                },
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::with_room_for;
    use vref_sim::Preset;

    #[test]
    fn a_preset_sized_world_is_the_presets() {
        let moi = Preset::Moi.config();
        assert_eq!(with_room_for(moi.clone(), None), moi);
        assert_eq!(with_room_for(moi.clone(), Some(8)), moi);
    }

    #[test]
    fn a_crowded_world_grows_with_its_cameras() {
        let moi = Preset::Moi.config();
        let big = with_room_for(moi.clone(), Some(64));
        assert!(big.workspace.area[0] > 2.0 * moi.workspace.area[0]);
        let ratio = big.robot.distance[1] / moi.robot.distance[1];
        let area_ratio = big.workspace.area[1] / moi.workspace.area[1];
        assert!(
            (ratio - area_ratio).abs() < 1e-9,
            "cameras scale with the area"
        );
    }
}
