//! hsv-run: assembles a vehicle from named models and runs the analyses of the hsv simulator.
//!
//! The binary (`hsv-run`) is a thin CLI over this library so tests and benches drive the same code.
//!
//! # One coupled time step, top down
//!
//! `hsv-run simulate` from the command line to a panel's pressure, in the order the code runs
//! (nine files; each line names where the next step lives):
//!
//! 1. [`commands::simulate`] parses the arguments and asks [`analysis::flight::Flight`] for the
//!    trimmed vehicle (assembled by name from the registry, [`vehicle::assemble`]), then flies it.
//! 2. [`analysis::simulate`] (`Stepper::step`) opens each 1 ms step: the controller's command
//!    ([`analysis::control`]), then `begin_step` on the vehicle.
//! 3. [`vehicle::partitioned`]'s `step.rs` (`begin_step`, `publish_regions`): the regions due at
//!    the accepted state are evaluated side by side and published (the body every step; the
//!    surfaces too with `surface_loads_dt_s`; module [`vehicle::region_rate`]).
//! 4. [`dynamics::integrate`] (`ExponentialRk4::step`) takes four stage derivatives; each calls
//!    the vehicle's `stage_derivative` with the open step `begin_step` returned (`interface.rs`):
//!    the regions' loads at the stage, each published on its topic in the data manager and
//!    read back by the coupling (`region_loads`, `step.rs`; [`vehicle::region_rate`]), then
//!    the body-surface interface closed by the configured
//!    fixed point (`close_interface`) over the equations of motion
//!    ([`dynamics::equations_of_motion`]).
//! 5. A lifting surface's loads ([`vehicle::regions::surface`], `surface_aero`): its Ritz-deformed mesh rotated
//!    by the elevon, its panels' velocities, then the aero model it was built with through the
//!    `AeroModel` trait (`hsv_core::aero`).
//! 6. `shock-expansion-piston` (`models/shock-expansion/src/piston.rs`): the steady
//!    shock-expansion flow along each strip (`steady.rs`), panel to panel by `wave::turn`,
//!    times the piston-theory factor of each panel's normal velocity.
//! 7. `wave::turn` calls the gas relations (`hsv_core::gas`): `small_turn`, `weak_oblique_turn`
//!    or `prandtl_meyer_expansion_from`, the formulas with their NACA 1135 and Anderson
//!    equation numbers.
//! 8. Back in `Stepper::step`, `commit_step` (`step.rs`) advances the heating (`heating.rs`,
//!    [`vehicle::regions::heated`]: conduction under the heat flux of the accepted state) and the sample is
//!    recorded ([`output`]).

pub mod aero_job;
pub mod analysis;
pub mod commands;
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

/// The controllers in the loop live with the analyses they serve ([`analysis::control`]); this
/// is their short path.
pub use analysis::control;
pub use linked::{registry, shared_registry};
