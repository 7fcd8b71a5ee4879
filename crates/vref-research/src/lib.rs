//! Experiments on vref's methods, kept apart from the product: each is an
//! example (`cargo run --release -p vref-research --example NAME`), and
//! this library holds what several of them share. No product crate
//! depends on this one.

pub mod live;
pub mod truth;
