//! Shock-expansion aerodynamics: the `shock-expansion` (steady, fidelity 3) and
//! `shock-expansion-piston` (steady mean flow plus local third-order piston theory, fidelity 4)
//! aero models.
//!
//! Both take no settings; an empty `[models.<name>]` table is accepted and any key in it is an
//! error naming the key path.

mod piston;
mod steady;
mod wave;

use hsv_core::aero::AeroModel;
use hsv_core::error::ModelError;
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};

pub use piston::ShockExpansionPiston;
pub use steady::ShockExpansion;
pub use wave::VACUUM_EDGE_MACH;

/// Registered name of [`ShockExpansion`].
pub const SHOCK_EXPANSION: &str = steady::NAME;
/// Registered name of [`ShockExpansionPiston`].
pub const SHOCK_EXPANSION_PISTON: &str = piston::NAME;

/// The models' settings: none (unknown keys are rejected).
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {}

/// Builds `shock-expansion` after checking its (empty) settings table.
fn build_shock_expansion(context: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    let Settings {} = context.parse_settings()?;
    Ok(Box::new(ShockExpansion::new()))
}

/// Builds `shock-expansion-piston` after checking its (empty) settings table.
fn build_shock_expansion_piston(
    context: &ModelContext<'_>,
) -> Result<Box<dyn AeroModel>, ModelError> {
    let Settings {} = context.parse_settings()?;
    Ok(Box::new(ShockExpansionPiston::new()))
}

hsv_core::register_model!(ModelDescriptor {
    name: steady::NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 3,
    summary: "Steady shock-expansion: oblique shock / Prandtl-Meyer from the freestream, then \
              panel to panel along strips (tangent wedge on unstructured meshes); beyond shock \
              detachment a modified-Newtonian pressure matched to the weak shock at theta_max, \
              continuous and monotone up to the pitot pressure at 90 deg",
    settings_doc: "",
    constructor: Constructor::Aero(build_shock_expansion),
});

hsv_core::register_model!(ModelDescriptor {
    name: piston::NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 4,
    summary: "Shock-expansion mean flow (modified Newtonian matched at theta_max past shock \
              detachment) plus local third-order piston theory for body rates and elastic panel \
              velocities",
    settings_doc: "",
    constructor: Constructor::Aero(build_shock_expansion_piston),
});
