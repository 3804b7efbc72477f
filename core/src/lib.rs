//! hsv-core: the contracts every hsv model implements and the physics they all share.
//!
//! Models and plugins depend on this crate only. It owns the role traits (aero, heat flux,
//! conduction, structure, propulsion), the `inventory` registry that names models, the
//! publish-subscribe data manager regions talk through, the US Standard Atmosphere 1976,
//! perfect-gas relations, frames, and panel meshes. SI units throughout.

pub mod acceleration;
pub mod atmosphere;
pub mod cache;
pub mod coupling;
pub mod frames;
pub mod gas;
pub mod geometry;
pub mod linalg;
pub mod material;
pub mod mesh;
pub mod region;
pub mod stl;
pub mod surface_grid;
pub mod testing;

pub mod aero;
pub mod control;
pub mod data;
pub mod error;
pub mod flow;
pub mod propulsion;
/// The aero capability of a reduced-order model ([`aero::reduced_order`]), by its short path.
pub use aero::reduced_order;
pub mod registry;
pub mod role;
pub mod settings;
pub mod structure;
pub mod thermal;

pub use error::ModelError;
/// Re-exported so [`register_model!`] works from crates that do not depend on `inventory`.
pub use inventory;
pub mod config;
pub mod plugin;
