//! hsv-run: assembles a vehicle from named models and runs the analyses of the hsv simulator.
//!
//! The binary (`hsv-run`) is a thin CLI over this library so tests and benches drive the same code.

pub mod aero_job;
pub mod analysis;
pub mod commands;
pub mod control;
pub mod disturbance;
pub mod dynamics;
pub mod error_line;
pub mod limits;
pub mod linked;
pub mod npz;
pub mod output;
pub mod progress;
pub mod steps;
pub mod vehicle;

pub use linked::{registry, shared_registry};
