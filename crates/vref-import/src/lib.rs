//! Importers for public graph-matching data, producing vref scene pairs.

mod cmu_house;
mod error;

pub use cmu_house::{CmuHouse, CmuHouseOptions};
pub use error::ImportError;
