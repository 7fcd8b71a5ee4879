//! The plain-text table of every command: vref_harness::table.

pub use vref_harness::table::Table;
