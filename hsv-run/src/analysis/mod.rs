//! Analyses built on the vehicle's regions: what a command runs, without its CLI and outputs.

pub mod flight;
pub mod flutter;
pub mod heating;
pub mod inputs;
pub mod linear_grid;
pub mod linearize;
pub mod shards;
pub mod simulate;
pub mod trade;
pub mod trim;
