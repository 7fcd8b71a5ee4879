#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::fs;
use std::path::Path;

use vref_import::{CmuHouse, CmuHouseOptions, ImportError};

fn options(gap: usize) -> CmuHouseOptions {
    CmuHouseOptions {
        gap,
        delaunay: true,
        features: true,
        keep: None,
        seed: 0,
    }
}

/// A three-frame, three-landmark sequence in the FGM layout.
fn fixture(dir: &Path) {
    for sub in ["label", "adj", "scf"] {
        fs::create_dir_all(dir.join(sub)).unwrap();
    }
    for k in 1..=3 {
        let shift = k as f64;
        let label = format!(
            "1.0e+001 2.0e+001\n{} 5.0e+001\n 7.0e+001  8.0e+001\n",
            30.0 + shift
        );
        fs::write(dir.join(format!("label/house{k}")), label).unwrap();
        fs::write(
            dir.join(format!("adj/house{k:03}.adj")),
            "0 1 0\n1 0 1\n0 1 0\n",
        )
        .unwrap();
        fs::write(dir.join(format!("scf/house{k:03}.scf")), "1 0\n0 1\n1 1\n").unwrap();
    }
}

#[test]
fn pairs_frames_at_the_gap_with_identity_ground_truth() {
    let dir = tempfile::tempdir().unwrap();
    fixture(dir.path());
    let house = CmuHouse::load(dir.path()).unwrap();
    assert_eq!(house.frames(), 3);
    let pairs = house.pairs(&options(1)).unwrap();
    assert_eq!(
        pairs.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(),
        ["house1-house2", "house2-house3"]
    );
    let p = &pairs[0];
    let mut truth = p.ground_truth.clone();
    truth.sort_unstable();
    assert_eq!(truth, vec![(0, 0), (1, 1), (2, 2)]);
    let h1 = &p.human.objects()[p.human.index_of(1).unwrap()];
    assert_eq!(h1.position.coords.as_slice(), &[31.0, 50.0, 0.0]);
    let r1 = &p.robot.objects()[p.robot.index_of(1).unwrap()];
    assert_eq!(r1.position.x, 32.0);
    assert_eq!(h1.feature, vec![0.0, 1.0]);
    assert_eq!(p.human.edge_ids().unwrap(), vec![[0, 1], [1, 2]]);
}

#[test]
fn without_options_graphs_are_fully_connected_and_featureless() {
    let dir = tempfile::tempdir().unwrap();
    fixture(dir.path());
    let opts = CmuHouseOptions {
        delaunay: false,
        features: false,
        ..options(0)
    };
    let pairs = CmuHouse::load(dir.path()).unwrap().pairs(&opts).unwrap();
    assert_eq!(pairs.len(), 3);
    assert!(pairs[0].human.edges().is_none());
    assert_eq!(pairs[0].human.feature_dim(), 0);
}

#[test]
fn malformed_files_are_named_with_their_line() {
    let dir = tempfile::tempdir().unwrap();
    fixture(dir.path());
    fs::write(dir.path().join("label/house2"), "1 2\n3 oops\n5 6\n").unwrap();
    match CmuHouse::load(dir.path()) {
        Err(ImportError::Parse {
            path,
            line,
            message,
        }) => {
            assert!(path.ends_with("label/house2"));
            assert_eq!(line, 2);
            assert!(message.contains("oops"));
        }
        other => panic!("{other:?}"),
    }

    fixture(dir.path());
    fs::write(dir.path().join("adj/house003.adj"), "0 1\n1 0\n0 1\n").unwrap();
    assert!(matches!(
        CmuHouse::load(dir.path()),
        Err(ImportError::Shape { .. })
    ));

    fixture(dir.path());
    fs::write(dir.path().join("scf/house001.scf"), "1 0\n0 1\n").unwrap();
    assert!(matches!(
        CmuHouse::load(dir.path()),
        Err(ImportError::Shape { .. })
    ));

    fixture(dir.path());
    fs::remove_file(dir.path().join("scf/house002.scf")).unwrap();
    assert!(matches!(
        CmuHouse::load(dir.path()),
        Err(ImportError::Io { .. })
    ));
}

#[test]
fn empty_directory_gap_and_keep_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    assert!(matches!(
        CmuHouse::load(dir.path()),
        Err(ImportError::NoFrames { .. })
    ));
    fixture(dir.path());
    let house = CmuHouse::load(dir.path()).unwrap();
    assert!(matches!(
        house.pairs(&options(3)),
        Err(ImportError::GapTooLarge { gap: 3, frames: 3 })
    ));
    for keep in [0, 4] {
        let opts = CmuHouseOptions {
            keep: Some(keep),
            ..options(0)
        };
        assert!(matches!(
            house.pairs(&opts),
            Err(ImportError::BadKeep { landmarks: 3, .. })
        ));
    }
}

#[test]
fn keep_chooses_per_view_and_restricts_edges() {
    let dir = tempfile::tempdir().unwrap();
    fixture(dir.path());
    let house = CmuHouse::load(dir.path()).unwrap();
    let opts = CmuHouseOptions {
        keep: Some(2),
        ..options(0)
    };
    for pair in house.pairs(&opts).unwrap() {
        assert_eq!((pair.human.len(), pair.robot.len()), (2, 2));
        for (h, r) in &pair.ground_truth {
            assert_eq!(h, r);
            assert!(pair.human.index_of(*h).is_some() && pair.robot.index_of(*r).is_some());
        }
        for [a, b] in pair.human.edge_ids().unwrap() {
            assert_eq!(
                a.abs_diff(b),
                1,
                "only Delaunay edges between kept landmarks"
            );
        }
    }
}
