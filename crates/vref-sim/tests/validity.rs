#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! Every generated scene is a valid dataset line, and its ids and order
//! give nothing away.

use std::io::BufReader;

use vref_scene::{DatasetReader, DatasetWriter, Limits};
use vref_sim::{Generator, Preset};

#[test]
fn every_scene_reads_back_through_validation_unchanged() {
    for preset in Preset::ALL {
        for seed in [3, 4] {
            let generator = Generator::new(preset.config(), seed)
                .unwrap()
                .named(preset.name());
            let pairs: Vec<_> = generator.scenes(25).map(|s| s.unwrap().pair).collect();
            let mut writer = DatasetWriter::new(Vec::new());
            for pair in &pairs {
                writer.write(pair).unwrap();
            }
            let bytes = writer.finish().unwrap();
            let read: Vec<_> = DatasetReader::new(BufReader::new(&bytes[..]), Limits::default())
                .collect::<Result<_, _>>()
                .unwrap();
            assert_eq!(read, pairs, "{preset} seed {seed}");
        }
    }
}

#[test]
fn features_have_the_configured_dimension_and_are_histograms() {
    for preset in Preset::ALL {
        let config = preset.config();
        let dim = config.features.dim();
        let colour = config.features.colour_weight;
        let colour_dim = dim - config.features.orientation_bins;
        let generator = Generator::new(config, 8).unwrap();
        for scene in generator.scenes(10) {
            let pair = scene.unwrap().pair;
            for graph in [&pair.robot, &pair.human] {
                assert_eq!(graph.feature_dim(), dim);
                for object in graph.objects() {
                    assert!(object.feature.iter().all(|&v| v >= 0.0));
                    let sum: f32 = object.feature[..colour_dim].iter().sum();
                    assert!(
                        (f64::from(sum) - colour).abs() < 1e-4,
                        "colour part sums to {sum}"
                    );
                }
            }
        }
    }
}

#[test]
fn ids_are_listed_in_order_and_unrelated_across_views() {
    let (mut pairs, mut same_id, mut same_index) = (0usize, 0usize, 0usize);
    for preset in Preset::ALL {
        let generator = Generator::new(preset.config(), 11).unwrap();
        for scene in generator.scenes(30) {
            let pair = scene.unwrap().pair;
            for graph in [&pair.robot, &pair.human] {
                let ids: Vec<u64> = graph.objects().iter().map(|o| o.id).collect();
                assert!(ids.windows(2).all(|w| w[0] < w[1]), "not sorted by id");
            }
            for &(h, r) in &pair.ground_truth {
                pairs += 1;
                same_id += usize::from(h == r);
                same_index += usize::from(pair.human.index_of(h) == pair.robot.index_of(r));
            }
        }
    }
    assert!(pairs > 300, "only {pairs} true pairs");
    assert_eq!(same_id, 0, "a true pair shares its id");
    // Random orders agree at about 1 in n places (n around 9 here).
    let share = same_index as f64 / pairs as f64;
    assert!(
        share < 0.25,
        "{share:.2} of true pairs sit at the same index"
    );
}
