//! The regions of the coupled vehicle as components (paper §III: "functions may be added,
//! exchanged, or removed without significant impact on the operation of other code
//! processes"): each file one region, its models, state and scratch, its evaluation at a state
//! (or its advance to a time), and the topics it publishes and reads. The regions exchange
//! their results only through the data manager ([`super::region_rate::RegionExchange`]); the
//! partitioned vehicle ([`super::partitioned`]) evaluates them at their rates, publishes what
//! they give and closes the body-surface interface from what it reads.
//!
//! | region | file | publishes | reads |
//! |---|---|---|---|
//! | main body | [`body`] | `main_body/loads`, `main_body/skin_friction` | body modes, controls |
//! | propulsion | [`engine`] | (with the body, on `main_body/loads`) | deformed underside, φ |
//! | followers (monolithic surfaces, fin) | [`follower`] | (with the body) | body modes, elevon |
//! | lifting surface | [`surface`] | `<surface>/loads` | own and body modes, elevon |
//! | heated surface | [`heated`], [`thermal`] | `<surface>/wall_heat_flux`, `<surface>/structure_temperatures` | its aero at the accepted state; the flux; the temperatures |

pub mod body;
pub mod engine;
pub mod follower;
pub mod heated;
pub mod surface;
pub mod thermal;

pub use hsv_core::coupling::ElevonCommand;

/// The controls at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct FlightControls {
    pub elevon: ElevonCommand,
    /// Fuel equivalence ratio φ.
    pub fuel_equivalence_ratio: f64,
}

/// Whether regions are evaluated side by side: only on a rayon worker thread (the simulation
/// loop runs on one). Called from outside the pool (trim, linearization, flutter), every
/// parallel section would hand its work to the pool and sleep on a latch, which cost 12 % of a
/// one-core run for two surface evaluations of about 70 µs each.
pub(in crate::vehicle) fn side_by_side() -> bool {
    rayon::current_thread_index().is_some()
}

/// `a` and `b` side by side when [`side_by_side`], one after the other otherwise.
pub(in crate::vehicle) fn join<RA: Send, RB: Send>(
    a: impl FnOnce() -> RA + Send,
    b: impl FnOnce() -> RB + Send,
) -> (RA, RB) {
    if side_by_side() {
        rayon::join(a, b)
    } else {
        (a(), b())
    }
}
