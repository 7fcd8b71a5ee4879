//! More objects than a preset draws get a larger world, not an error.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use vref_config::FeedSettings;
use vref_feed::{synthetic_world, with_room_for};
use vref_scene::Side;
use vref_sim::Preset;

#[test]
fn a_preset_sized_world_is_the_presets() {
    let moi = Preset::Moi.config();
    assert_eq!(with_room_for(moi.clone(), None), moi);
    assert_eq!(with_room_for(moi.clone(), Some(8)), moi);
}

#[test]
fn a_crowded_world_grows_and_both_views_see_most_objects() {
    let moi = Preset::Moi.config();
    let big = with_room_for(moi.clone(), Some(64));
    assert!(big.workspace.area[0] > 2.0 * moi.workspace.area[0]);
    let ratio = big.robot.distance[1] / moi.robot.distance[1];
    let area_ratio = big.workspace.area[1] / moi.workspace.area[1];
    assert!(
        (ratio - area_ratio).abs() < 1e-9,
        "cameras scale with the area"
    );
    let feeds = FeedSettings::default();
    for n in [32, 64] {
        let (_, world) = synthetic_world(&feeds, Some(n)).unwrap();
        assert_eq!(world.object_count(), n);
        for side in [Side::Robot, Side::Human] {
            let seen = world.detected(side, 10.0).len();
            assert!(seen >= n / 2, "{n} objects, {side} sees {seen}");
        }
    }
}
