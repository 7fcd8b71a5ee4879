//! Importers for public graph-matching data, producing vref scene pairs.

mod bop;
mod cmu_house;
mod error;

pub use bop::{
    BopDataset, BopImport, BopOptions, BopScene, BopSceneDir, BopView, HUMAN_IDS, MeasuredView,
    ROBOT_IDS, datasets_in, outline, track_ids,
};
pub use cmu_house::{CmuHouse, CmuHouseOptions};
pub use error::ImportError;
