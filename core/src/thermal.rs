//! The two thermal roles: heat flux into the wall from the flow, and conduction in the structure.

use nalgebra::DVector;

use crate::aero::AeroSolution;
use crate::error::ModelError;
use crate::flow::FlightCondition;
use crate::mesh::PanelMesh;
use crate::surface_grid::SurfaceGrid;

/// Stefan-Boltzmann constant σ, W/(m² K⁴) (CODATA 2018, exact), for re-radiation εσT⁴.
pub const STEFAN_BOLTZMANN_W_M2_K4: f64 = 5.670_374_419e-8;

/// Checks what every conduction step receives: a finite, positive time step (s) and a finite
/// heat flux (W/m²) on every panel.
pub fn check_step_inputs(model: &str, flux_w_m2: &[f64], dt_s: f64) -> Result<(), ModelError> {
    if !(dt_s.is_finite() && dt_s > 0.0) {
        return Err(ModelError::out_of_range(
            model,
            "time step (s)",
            dt_s,
            "finite and > 0",
        ));
    }
    if let Some(i) = flux_w_m2.iter().position(|q| !q.is_finite()) {
        return Err(ModelError::out_of_range(
            model,
            &format!("heat flux (W/m^2) at panel {i}"),
            flux_w_m2[i],
            "finite",
        ));
    }
    Ok(())
}

/// Checks what every heat-flux model receives: one edge state, wall temperature and output
/// slot per panel of `mesh`, and a finite flight condition.
pub fn check_heat_flux_inputs(
    model: &str,
    mesh: &PanelMesh,
    flight: &FlightCondition,
    aero: &AeroSolution,
    wall_temperature_k: &[f64],
    out_w_m2: &[f64],
) -> Result<(), ModelError> {
    check_wall_inputs(
        model,
        mesh,
        flight,
        aero,
        wall_temperature_k,
        ("heat-flux outputs", out_w_m2.len()),
    )
}

/// Checks what every [`SkinFriction::wall_shear`] call receives: one edge state, wall temperature
/// and output slot per panel of `mesh`, and a finite flight condition.
pub fn check_wall_shear_inputs(
    model: &str,
    mesh: &PanelMesh,
    flight: &FlightCondition,
    aero: &AeroSolution,
    wall_temperature_k: &[f64],
    out_pa: &[f64],
) -> Result<(), ModelError> {
    check_wall_inputs(
        model,
        mesh,
        flight,
        aero,
        wall_temperature_k,
        ("wall-shear outputs", out_pa.len()),
    )
}

/// One entry per panel in every per-panel input and in the output named by `output`.
fn check_wall_inputs(
    model: &str,
    mesh: &PanelMesh,
    flight: &FlightCondition,
    aero: &AeroSolution,
    wall_temperature_k: &[f64],
    output: (&str, usize),
) -> Result<(), ModelError> {
    let n = mesh.panels.len();
    for (what, len) in [
        ("edge states", aero.edge.len()),
        ("wall temperatures", wall_temperature_k.len()),
        output,
    ] {
        if len != n {
            return Err(ModelError::inconsistent(
                model,
                format!("{len} {what} for a mesh of {n} panels"),
            ));
        }
    }
    flight.check_finite()
}

/// r = Pr^(1/2) laminar, Pr^(1/3) turbulent (Anderson, Hypersonic §6.7 and §6.10): the
/// recovery factor every heat-flux model's adiabatic wall uses.
pub fn recovery_factor(prandtl_number: f64, turbulent: bool) -> f64 {
    if turbulent {
        prandtl_number.cbrt()
    } else {
        prandtl_number.sqrt()
    }
}

/// T_aw = T_e (1 + r (γ−1)/2 M_e²), K: the adiabatic-wall (recovery) temperature (Anderson,
/// Hypersonic §6.7).
pub fn recovery_temperature_k(edge_temperature_k: f64, mach: f64, gamma: f64, r: f64) -> f64 {
    edge_temperature_k * (1.0 + r * 0.5 * (gamma - 1.0) * mach * mach)
}

/// Checks 0 < T_w ≤ melting point (K) for heat-flux model `model`, naming the panel if given:
/// a wall above its melting point has no meaningful heat flux.
pub fn check_wall_temperature(
    model: &str,
    wall_temperature_k: f64,
    melting_point_k: f64,
    panel: Option<usize>,
) -> Result<(), ModelError> {
    // Built only on failure: this runs per panel in the time loop, which allocates nothing.
    let at = || panel.map_or_else(String::new, |p| format!(" at panel {p}"));
    if !(wall_temperature_k.is_finite() && wall_temperature_k > 0.0) {
        return Err(ModelError::out_of_range(
            model,
            &format!("wall temperature (K){}", at()),
            wall_temperature_k,
            "finite and > 0",
        ));
    }
    if wall_temperature_k > melting_point_k {
        return Err(ModelError::out_of_range(
            model,
            &format!("wall temperature (K){}: the structure has melted", at()),
            wall_temperature_k,
            format!("<= melting point {melting_point_k} K"),
        ));
    }
    Ok(())
}

/// Aeroheating: the net heat flux into the structure at every panel of a wetted mesh.
pub trait HeatFluxModel: Send {
    /// The registered name (`eckert`, `kriging-stanton`, ...).
    fn name(&self) -> &str;

    /// Net heat flux into the wall (convection minus re-radiation), W/m², positive into the
    /// structure, for every panel of `mesh`, from the edge states of an aero evaluation and the
    /// wall temperature of each panel (K).
    fn heat_flux(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        aero: &AeroSolution,
        wall_temperature_k: &[f64],
        out_w_m2: &mut [f64],
    ) -> Result<(), ModelError>;

    /// Wall shear from the same boundary layer, if the model has a skin-friction law (skin
    /// friction is an optional capability: `None` by default, as for structure capabilities).
    fn skin_friction(&mut self) -> Option<&mut dyn SkinFriction> {
        None
    }
}

/// Skin friction of a heat-flux model whose boundary layer has a wall-shear law: what turns the
/// boundary layer into viscous loads ([`crate::aero::integrate_shear`]).
pub trait SkinFriction {
    /// Wall shear stress τ_w ≥ 0, Pa, on every panel of `mesh`, from the edge states of an aero
    /// evaluation and the wall temperature of each panel (K). The stress acts along the local
    /// edge flow; [`crate::aero::integrate_shear`] gives it that direction.
    fn wall_shear(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        aero: &AeroSolution,
        wall_temperature_k: &[f64],
        out_pa: &mut [f64],
    ) -> Result<(), ModelError>;
}

/// A cache a model was built from: its file and whether it was reused or (re)built.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CacheUse {
    pub path: std::path::PathBuf,
    /// True when the file held what the model needed; false when the model built it anew.
    pub reused: bool,
    /// What the model made of the cache beyond reuse, for the run's warnings (e.g. fewer modes
    /// than set because the training gave fewer snapshots).
    pub note: Option<String>,
}

/// Transient heat conduction in a structure, advanced by the heat flux on its wetted panels.
///
/// The thermal state is plain data owned by the caller (a full temperature field or POD
/// coefficients), so a run can be cloned, rolled back and linearized.
pub trait ConductionModel: Send {
    /// The registered name (`full-order`, `pod`, ...).
    fn name(&self) -> &str;

    /// Length of the thermal state vector.
    fn n_states(&self) -> usize;

    /// Number of structural nodes whose temperature [`Self::node_temperatures`] reports.
    fn n_nodes(&self) -> usize;

    /// Number of wetted panels that [`Self::step`] takes a heat flux for and
    /// [`Self::surface_temperatures`] reports.
    fn n_surface_panels(&self) -> usize;

    /// State of a structure at a uniform temperature (K).
    fn uniform_state(&self, temperature_k: f64) -> Result<DVector<f64>, ModelError>;

    /// Advances `state` by `dt_s` seconds under the given surface heat flux (W/m² per panel).
    fn step(
        &mut self,
        state: &mut DVector<f64>,
        surface_heat_flux_w_m2: &[f64],
        dt_s: f64,
    ) -> Result<(), ModelError>;

    /// [`Self::step`] through the scratch `trial`, so a failed step leaves `state` as it was
    /// (the last good one): the one conduction step of every heating loop.
    fn advance(
        &mut self,
        state: &mut DVector<f64>,
        trial: &mut DVector<f64>,
        surface_heat_flux_w_m2: &[f64],
        dt_s: f64,
    ) -> Result<(), ModelError> {
        trial.copy_from(state);
        self.step(trial, surface_heat_flux_w_m2, dt_s)?;
        std::mem::swap(state, trial);
        Ok(())
    }

    /// Wall temperature of each wetted panel, K.
    fn surface_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]);

    /// Temperature of each structural node, K (what the structure model degrades stiffness from).
    fn node_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]);

    /// Through-thickness temperature difference of the structure at each node, K: its lower
    /// face (z down, the larger z) minus its upper face, what a plate's thermal moment comes
    /// from. Models without through-thickness resolution report zeros.
    fn node_temperature_differences(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        let _ = state;
        out_k.fill(0.0);
    }

    /// The cache file the model was built from (a reduced model's basis), if any.
    fn cache(&self) -> Option<CacheUse> {
        None
    }

    /// The surface grid whose nodes [`Self::node_temperatures`] reports on, if the model has
    /// one: what a structure's temperature grid is interpolated from
    /// ([`crate::coupling::GridTransfer`]).
    fn node_grid(&self) -> Option<&SurfaceGrid> {
        None
    }
}
