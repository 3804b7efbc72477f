//! Analyses built on the vehicle's regions: what a command runs, without its CLI and outputs.

pub mod heating;
pub mod trim;
