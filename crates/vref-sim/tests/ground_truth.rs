#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! The ground truth pairs exactly the objects both cameras detect, and the
//! reported positions are where those objects are, in each camera's frame.

use nalgebra::{Point3, Vector3};
use vref_scene::{SceneGraph, Side};
use vref_sim::{GeneratedScene, Generator, Preset};

/// How the sensors err in a test.
#[derive(Clone, Copy, PartialEq)]
enum Sensors {
    AsConfigured,
    /// No random error, but positions are depth centroids of the seen
    /// surface.
    FrontSurfaceOnly,
    Perfect,
}

fn scenes(preset: Preset, seed: u64, count: u64, sensors: Sensors) -> Vec<GeneratedScene> {
    let config = match sensors {
        Sensors::AsConfigured => preset.config(),
        Sensors::Perfect => preset.config().noiseless(),
        Sensors::FrontSurfaceOnly => {
            let mut config = preset.config().noiseless();
            config.robot.noise.surface_bias = 1.0;
            config.human.noise.surface_bias = 1.0;
            config
        }
    };
    let generator = Generator::new(config, seed).unwrap();
    generator.scenes(count).map(Result::unwrap).collect()
}

fn position(graph: &SceneGraph, id: u64) -> Point3<f64> {
    graph.objects()[graph.index_of(id).unwrap()].position
}

#[test]
fn ground_truth_is_exactly_the_objects_seen_by_both() {
    for preset in Preset::ALL {
        for scene in scenes(preset, 21, 30, Sensors::AsConfigured) {
            let both = scene.seen_by_both();
            let expected: Vec<(u64, u64)> = {
                let mut pairs: Vec<_> = both
                    .iter()
                    .map(|&k| (scene.human.id_of(k).unwrap(), scene.robot.id_of(k).unwrap()))
                    .collect();
                pairs.sort_unstable();
                pairs
            };
            assert_eq!(scene.pair.ground_truth, expected, "{}", scene.pair.name);
            for side in [Side::Robot, Side::Human] {
                let (view, graph) = view_and_graph(&scene, side);
                // One graph object per sighting, and no other.
                assert_eq!(graph.len(), view.sightings.len());
                for s in &view.sightings {
                    assert!(graph.index_of(s.id).is_some());
                    assert!(s.object < scene.objects.len());
                }
                let objects = view.objects();
                assert!(
                    objects.windows(2).all(|w| w[0] < w[1]),
                    "a world object seen twice"
                );
            }
        }
    }
}

#[test]
fn views_are_partial_so_both_graphs_have_objects_without_partner() {
    for preset in Preset::ALL {
        let (mut world, mut unpartnered_human, mut unpartnered_robot, mut unseen) = (0, 0, 0, 0);
        for scene in scenes(preset, 22, 30, Sensors::AsConfigured) {
            let gt = scene.pair.ground_truth.len();
            world += scene.objects.len();
            unpartnered_human += scene.pair.human.len() - gt;
            unpartnered_robot += scene.pair.robot.len() - gt;
            unseen += (0..scene.objects.len())
                .filter(|&k| scene.human.id_of(k).is_none() && scene.robot.id_of(k).is_none())
                .count();
        }
        // Partial, not empty: most objects are matched, some are not.
        assert!(unpartnered_human > 0 && unpartnered_robot > 0, "{preset}");
        assert!(
            unpartnered_human + unpartnered_robot + unseen < world / 2,
            "{preset}"
        );
    }
}

#[test]
fn detected_objects_are_in_front_of_the_camera_and_in_its_image() {
    for preset in Preset::ALL {
        let min_fraction = [
            preset.config().robot.min_visible_fraction,
            preset.config().human.min_visible_fraction,
        ];
        for scene in scenes(preset, 23, 20, Sensors::AsConfigured) {
            for (side, min) in [Side::Robot, Side::Human].into_iter().zip(min_fraction) {
                let view = scene.view(side);
                let camera = &view.camera;
                // Camera frame: y down, so the world's up points to -y.
                assert!(camera.direction_to_camera(&Vector3::z()).y < 0.0);
                for s in &view.sightings {
                    assert!(s.visible_fraction >= min && s.visible_fraction <= 1.0 + 1e-9);
                    let centre = camera.to_camera(&scene.objects[s.object].centre);
                    assert!(centre.z > 0.0);
                    let [u, v] = camera.project(&centre).unwrap();
                    // The centre may lie just outside a truncated object's
                    // visible part, never far outside the image.
                    assert!(u.abs() < camera.width_px && v.abs() < camera.height_px);
                }
            }
        }
    }
}

#[test]
fn perfect_sensors_report_each_centre_in_each_camera_frame() {
    for preset in Preset::ALL {
        for scene in scenes(preset, 24, 20, Sensors::Perfect) {
            for side in [Side::Robot, Side::Human] {
                let (view, graph) = view_and_graph(&scene, side);
                for s in &view.sightings {
                    let truth = view.camera.to_camera(&scene.objects[s.object].centre);
                    let seen = position(graph, s.id);
                    assert!((seen - truth).norm() < 1e-9, "{}: {side}", scene.pair.name);
                }
            }
            // Both frames are rigid images of the world: true pairs keep
            // their distances exactly.
            let both = scene.seen_by_both();
            for (i, &a) in both.iter().enumerate() {
                for &b in &both[i + 1..] {
                    let (dh, dr) = distances(&scene, a, b);
                    let world = (scene.objects[a].centre - scene.objects[b].centre).norm();
                    assert!((dh - world).abs() < 1e-9 && (dr - world).abs() < 1e-9);
                }
            }
        }
    }
}

#[test]
fn depth_centroids_lie_on_the_front_of_each_object() {
    for preset in Preset::ALL {
        for scene in scenes(preset, 24, 20, Sensors::FrontSurfaceOnly) {
            for side in [Side::Robot, Side::Human] {
                let (view, graph) = view_and_graph(&scene, side);
                for s in &view.sightings {
                    let object = &scene.objects[s.object];
                    let truth = view.camera.to_camera(&object.centre);
                    let seen = position(graph, s.id);
                    let off = (seen - truth).norm();
                    assert!(
                        off <= object.shape.bounding_radius(),
                        "{}: {side} object {} is {off:.3} m from its centre",
                        scene.pair.name,
                        s.object,
                    );
                    // Only the camera-facing surface is seen.
                    assert!(seen.coords.norm() < truth.coords.norm());
                }
            }
        }
    }
}

#[test]
fn front_surface_bias_deforms_distances_by_less_than_the_objects_sizes() {
    for preset in Preset::ALL {
        let (mut total, mut radii, mut count) = (0.0, 0.0, 0.0);
        for scene in scenes(preset, 25, 20, Sensors::FrontSurfaceOnly) {
            let both = scene.seen_by_both();
            for (i, &a) in both.iter().enumerate() {
                for &b in &both[i + 1..] {
                    let (dh, dr) = distances(&scene, a, b);
                    let size = scene.objects[a].shape.bounding_radius()
                        + scene.objects[b].shape.bounding_radius();
                    // Each view measures each object's own front surface.
                    assert!(
                        (dh - dr).abs() <= 2.0 * size,
                        "{}: {dh} vs {dr}",
                        scene.pair.name
                    );
                    total += (dh - dr).abs();
                    radii += 0.5 * size;
                    count += 1.0;
                }
            }
        }
        let (mean, mean_radius) = (total / count, radii / count);
        assert!(
            mean > 0.05 * mean_radius,
            "{preset}: views agree, no front-surface bias"
        );
        assert!(
            mean < mean_radius,
            "{preset}: distances differ by {mean:.3} m on average"
        );
    }
}

fn view_and_graph(scene: &GeneratedScene, side: Side) -> (&vref_sim::View, &SceneGraph) {
    match side {
        Side::Robot => (&scene.robot, &scene.pair.robot),
        Side::Human => (&scene.human, &scene.pair.human),
    }
}

/// Distance between world objects `a` and `b` in the human and the robot
/// graph.
fn distances(scene: &GeneratedScene, a: usize, b: usize) -> (f64, f64) {
    let (h, r, p) = (&scene.human, &scene.robot, &scene.pair);
    let dh =
        (position(&p.human, h.id_of(a).unwrap()) - position(&p.human, h.id_of(b).unwrap())).norm();
    let dr =
        (position(&p.robot, r.id_of(a).unwrap()) - position(&p.robot, r.id_of(b).unwrap())).norm();
    (dh, dr)
}
