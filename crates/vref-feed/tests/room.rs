//! More objects than a preset draws get a larger world, not an error.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use vref_config::FeedSettings;
use vref_feed::synthetic_world;
use vref_scene::Side;

#[test]
fn a_crowded_world_has_its_objects_and_both_views_see_most_of_them() {
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
