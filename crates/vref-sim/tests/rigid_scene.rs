#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! The rigid scenes `vref bench solver` times and `vref scenes --preset
//! rigid` writes.

use nalgebra::Point3;
use vref_match::{Method, Params, Problem, solve};
use vref_scene::SceneGraph;
use vref_sim::{RigidScene, RigidSceneError};

fn distances(g: &SceneGraph) -> Vec<f64> {
    let o = g.objects();
    let mut d: Vec<f64> = (0..o.len())
        .flat_map(|i| (i + 1..o.len()).map(move |j| (i, j)))
        .map(|(i, j)| (o[i].position - o[j].position).norm())
        .collect();
    d.sort_by(f64::total_cmp);
    d
}

fn distances_from(g: &SceneGraph, p: Point3<f64>) -> Vec<f64> {
    let mut d: Vec<f64> = g
        .objects()
        .iter()
        .map(|o| (o.position - p).norm())
        .collect();
    d.sort_by(f64::total_cmp);
    d
}

#[test]
fn scenes_have_the_exact_size_and_are_rigid_up_to_noise() {
    let scene = RigidScene::new(12, 3).unwrap();
    assert_eq!((scene.human.len(), scene.robot.len()), (12, 12));
    assert_eq!(scene.human.feature_dim(), 48);
    for (h, r) in distances(&scene.human).iter().zip(distances(&scene.robot)) {
        assert!(
            (h - r).abs() < 20.0 * RigidScene::POSITION_NOISE,
            "{h} vs {r}"
        );
    }
    let again = RigidScene::new(12, 3).unwrap();
    assert_eq!(scene.robot, again.robot);
}

#[test]
fn the_pair_carries_the_true_correspondence() {
    let scene = RigidScene::new(9, 4).unwrap();
    let pair = scene.pair("rigid".to_owned()).unwrap();
    assert_eq!(pair.ground_truth.len(), 9);
    for &(h, r) in &pair.ground_truth {
        let hf = &pair.human.objects()[h as usize].feature;
        let rf = &pair.robot.objects()[r as usize].feature;
        let gap: f32 = hf.iter().zip(rf).map(|(a, b)| (a - b).abs()).sum::<f32>() / hf.len() as f32;
        assert!(gap < 0.2, "human {h} and robot {r} differ by {gap}");
    }
}

#[test]
fn a_move_changes_one_human_object() {
    let scene = RigidScene::new(10, 5).unwrap();
    let moved = scene.moved(13, 9).unwrap();
    let changed: Vec<usize> = (0..10)
        .filter(|&k| scene.human.objects()[k] != moved.human.objects()[k])
        .collect();
    assert_eq!(changed, vec![3]);
    let step = (scene.human.objects()[3].position - moved.human.objects()[3].position).norm();
    assert!((step - 0.05).abs() < 1e-9);
}

#[test]
fn upright_scenes_carry_the_moved_up_vector() {
    let scene = RigidScene::new(8, 2).unwrap().upright().unwrap();
    assert_eq!(
        scene.human.up().map(|u| [u.x, u.y, u.z]),
        Some([0.0, 0.0, 1.0])
    );
    let up = scene.robot.up().unwrap();
    assert!((up.norm() - 1.0).abs() < 1e-12);
    // Heights above the human view's floor are kept along the robot's up.
    let (h, r) = (scene.human.objects(), scene.robot.objects());
    let pair = scene.pair("up".to_owned()).unwrap();
    for &(a, b) in &pair.ground_truth {
        for &(c, d) in &pair.ground_truth {
            let rise_h = h[c as usize].position.z - h[a as usize].position.z;
            let rise_r = up.dot(&(r[d as usize].position - r[b as usize].position));
            assert!((rise_h - rise_r).abs() < 20.0 * RigidScene::POSITION_NOISE);
        }
    }
}

#[test]
fn rrwm_recovers_the_rigid_correspondence() {
    let scene = RigidScene::new(10, 1).unwrap();
    let problem = Problem::new(&scene.human, &scene.robot, 0.01).unwrap();
    let solution = solve(Method::Rrwm, &problem, &Params::default()).unwrap();
    let pairs = solution.id_pairs(&scene.human, &scene.robot);
    // The robot objects are a shuffled copy: their positions tell the
    // permutation back.
    let right = pairs
        .iter()
        .filter(|&&(h, r)| {
            let hp = scene.human.objects()[h as usize].position;
            let rp = scene.robot.objects()[r as usize].position;
            let hd = distances_from(&scene.human, hp);
            let rd = distances_from(&scene.robot, rp);
            hd.iter().zip(&rd).all(|(a, b)| (a - b).abs() < 0.02)
        })
        .count();
    assert_eq!(right, 10);
}

#[test]
fn bad_sizes_and_noise_are_refused_and_noise_moves_only_the_robot() {
    for noise in [-0.001, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            RigidScene::with_noise(6, 1, noise),
            Err(RigidSceneError::BadNoise(_))
        ));
    }
    assert_eq!(
        RigidScene::new(1, 0).err(),
        Some(RigidSceneError::TooFewObjects(1))
    );
    // More noise moves the same draws farther: the scene is otherwise
    // the same.
    let (a, b) = (
        RigidScene::new(6, 1).unwrap(),
        RigidScene::with_noise(6, 1, 0.02).unwrap(),
    );
    assert_eq!(a.human, b.human);
    assert_ne!(a.robot, b.robot);
}
