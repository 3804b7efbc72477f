//! Analyses built on the vehicle's regions: what a command runs, without its CLI and outputs.

pub mod control;
pub mod flight;
pub mod flutter;
pub mod heating;
pub mod inputs;
pub mod level_trim;
pub mod linear_grid;
pub mod linearize;
pub mod shards;
pub mod simulate;
pub mod trade;
pub mod trim;
