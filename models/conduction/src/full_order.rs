//! The `full-order` conduction model: transient heat conduction in the extruded lifting-surface
//! grid ([`crate::grid`]), backward Euler in time with Picard iteration on the
//! temperature-dependent conductivity and heat capacity.
//!
//! Semi-discrete equations (Galerkin finite elements; Lewis, Nithiarasu & Seetharamu,
//! Fundamentals of the Finite Element Method for Heat and Fluid Flow, 2004, ch. 7):
//! C(T) dT/dt + K(T) T = F, with K = Σ_e k_e(T̄_e) G_e (k at the element's mean temperature),
//! C = diag(Σ_materials ρ c_p(T) V) (lumped), F = Σ_panels w q A (the panel's heat flux times its
//! area, spread over the 4 face nodes below its centroid with bilinear weights, or for a panel
//! facing sideways over the side face through the whole stack ([`PanelMap`]); the weights of a
//! panel sum to 1, so Σ F = Σ q A exactly). All other boundaries are adiabatic.
//!
//! Backward Euler with the capacity at the step's midpoint temperature,
//! C(½(Tⁿ + Tⁿ⁺¹)) (Tⁿ⁺¹ − Tⁿ)/Δt + K(Tⁿ⁺¹) Tⁿ⁺¹ = F, conserves energy exactly for a c_p linear in
//! T (Σ_i ∫ρ c_p dT = Δt Σ F, because K's rows sum to zero) and is unconditionally stable
//! (L-stable; Hughes, The Finite Element Method, §8.2). Picard iteration: properties at the
//! latest iterate, a banded Cholesky solve per iteration, until the largest change is below
//! `picard_tolerance_k`. Materials whose properties do not depend on temperature are solved in
//! one factorization per time step size.
//!
//! **Built-up structure** (`skin_thickness_m`): two skins of the structural material at the
//! plate's faces and an interior between them (default still air, core `material/air.rs`) that
//! conducts only: radiation and convection between the skins are neglected, which leaves the
//! interior nearly adiabatic (the usual assumption for the skins of a hollow control surface).
//! The structure the plate model sees is then the two skins
//! ([`ThermalGrid::structure_average_weights`], [`ThermalGrid::structure_difference_weights`]:
//! the skins' mean temperatures).
//!
//! The settings and their checks are in `settings.rs` (re-exported here).

// Index loops mirror the matrix algebra they implement.
#![allow(clippy::needless_range_loop)]

use hsv_core::error::ModelError;
use hsv_core::linalg::BandedMatrix;
use hsv_core::material::Material;
use hsv_core::mesh::{PanelMesh, RegionKind};
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::{ConductionModel, check_step_inputs};
use nalgebra::DVector;

use crate::grid::{Layer, LayerKind, ThermalGrid};

pub use crate::settings::{LayerSetting, SETTINGS_DOC, Settings};

/// Registered name.
pub const NAME: &str = "full-order";

/// Where each panel of the wetted mesh meets the grid: the dofs its heat enters with their
/// weights (summing to 1), and the area through which its heat flux enters (0 for panels that
/// are not wetted lifting-surface panels, e.g. the root cap against the body).
///
/// A panel facing up or down (normal within 45° of the grid's normal) meets the upper or lower
/// face: the 4 face dofs under its centroid, bilinear weights. A panel facing sideways (the tip
/// face) meets the grid's side face, which spans the whole stack: bilinear weights along the
/// edge times [`ThermalGrid::side_face_weights`] through the thickness. So a symmetric section
/// under a symmetric flux is loaded symmetrically (sending the tip's heat to one face made a
/// false through-thickness difference of ~10 K at the tip).
#[derive(Debug, Clone, PartialEq)]
pub struct PanelMap {
    /// Panel p's entries are `start[p]..start[p + 1]` of `dofs` and `weights`.
    pub start: Vec<usize>,
    pub dofs: Vec<usize>,
    pub weights: Vec<f64>,
    pub loaded_area_m2: Vec<f64>,
}

impl PanelMap {
    pub fn n_panels(&self) -> usize {
        self.loaded_area_m2.len()
    }

    /// (dof, weight) of panel `p`.
    pub fn entries(&self, p: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.start[p]..self.start[p + 1];
        self.dofs[range.clone()]
            .iter()
            .copied()
            .zip(self.weights[range].iter().copied())
    }
}

/// Revision of `map_panels`, part of a POD basis's fingerprint: a basis trained from
/// snapshots of an earlier map (revision 1 sent the tip face's heat to the lower face) is
/// retrained rather than reused.
pub const PANEL_MAP_REVISION: u32 = 2;

/// |n · up| below which a panel faces sideways: cos 45°, halfway between a face and the side.
const SIDE_FACING_COSINE: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Builds the panel map (see [`PanelMap`]).
fn map_panels(
    grid: &SurfaceGrid,
    thermal: &ThermalGrid,
    mesh: &PanelMesh,
) -> Result<PanelMap, ModelError> {
    let points = grid
        .map_panels(mesh)
        .map_err(|e| ModelError::inconsistent(NAME, e.to_string()))?;
    let top = thermal.n_levels - 1;
    let mut map = PanelMap {
        start: Vec::with_capacity(points.len() + 1),
        dofs: Vec::with_capacity(4 * points.len()),
        weights: Vec::with_capacity(4 * points.len()),
        loaded_area_m2: Vec::with_capacity(points.len()),
    };
    map.start.push(0);
    for (panel, point) in mesh.panels.iter().zip(&points) {
        let up: nalgebra::Vector3<f64> = (0..4)
            .map(|a| point.weights[a] * thermal.up[point.nodes[a]])
            .sum();
        let facing = panel.normal.dot(&up.normalize());
        for (&node, &w) in point.nodes.iter().zip(&point.weights) {
            if facing.abs() >= SIDE_FACING_COSINE {
                let level = if facing > 0.0 { top } else { 0 };
                map.dofs.push(thermal.dof(node, level));
                map.weights.push(w);
            } else {
                for (level, share) in thermal.side_face_weights(node) {
                    map.dofs.push(thermal.dof(node, level));
                    map.weights.push(w * share);
                }
            }
        }
        map.start.push(map.dofs.len());
        let wetted = mesh.surfaces[usize::from(panel.surface)].region == RegionKind::LiftingSurface;
        map.loaded_area_m2
            .push(if wetted { panel.area_m2 } else { 0.0 });
    }
    Ok(map)
}

/// A material whose table has the same k and c_p in every row.
fn has_constant_thermal_properties(m: &Material) -> bool {
    m.table.windows(2).all(|w| {
        w[0].conductivity_w_m_k == w[1].conductivity_w_m_k
            && w[0].specific_heat_j_kg_k == w[1].specific_heat_j_kg_k
    })
}

fn material_error(e: hsv_core::material::MaterialError) -> ModelError {
    e.into_model_error(NAME)
}

/// The full-order conduction model (module docs). Scratch only; the state is the temperature
/// of every dof in grid order.
#[derive(Debug, Clone)]
pub struct FullOrder {
    settings: Settings,
    /// The surface grid the thermal grid is built through (node temperatures are on it).
    plate: SurfaceGrid,
    grid: ThermalGrid,
    materials: Vec<Material>,
    constant_properties: bool,
    panels: PanelMap,
    /// Weights over a plate node's levels: the structure's mean temperature.
    node_average: Vec<(usize, f64)>,
    /// Weights over a plate node's levels: the structure's lower-minus-upper difference.
    node_difference: Vec<(usize, f64)>,
    // Scratch.
    matrix: BandedMatrix,
    factored_dt_s: Option<f64>,
    load: Vec<f64>,
    capacity: Vec<f64>,
    iterate: Vec<f64>,
    solution: Vec<f64>,
    picard_iterations: usize,
}

impl FullOrder {
    /// The model over `grid` (the structural grid of the lifting surface) with the wetted panel
    /// mesh `mesh` of the same surface.
    pub fn new(
        grid: &SurfaceGrid,
        mesh: &PanelMesh,
        settings: Settings,
    ) -> Result<Self, ModelError> {
        if let Some((key, value, allowed)) = settings.first_invalid() {
            return Err(ModelError::out_of_range(NAME, &key, value, allowed));
        }
        if let Some((key, value, allowed)) = settings.skins_misfit(grid) {
            return Err(ModelError::out_of_range(NAME, &key, value, allowed));
        }
        let mut materials = vec![
            settings
                .structure_material
                .resolve()
                .map_err(material_error)?,
        ];
        let mut outer = Vec::new();
        for layer in &settings.layers {
            materials.push(layer.material.resolve().map_err(material_error)?);
            outer.push(Layer {
                thickness_m: Some(layer.thickness_m),
                kind: LayerKind::Outer,
                material: materials.len() - 1,
                sublayers: layer.sublayers,
            });
        }
        // Lower face first: outermost lower layer, ..., the plate (the solid structure, or lower
        // skin, interior, upper skin), ..., outermost upper layer.
        let mut stack: Vec<Layer> = outer.clone();
        match settings.skin_thickness_m {
            None => stack.push(Layer {
                thickness_m: None,
                kind: LayerKind::Structure,
                material: 0,
                sublayers: settings.structure_sublayers,
            }),
            Some(skin_m) => {
                materials.push(
                    settings
                        .interior_material
                        .resolve()
                        .map_err(material_error)?,
                );
                let skin = Layer {
                    thickness_m: Some(skin_m),
                    kind: LayerKind::Structure,
                    material: 0,
                    sublayers: settings.structure_sublayers,
                };
                let interior = Layer {
                    thickness_m: None,
                    kind: LayerKind::Interior,
                    material: materials.len() - 1,
                    sublayers: settings.interior_sublayers,
                };
                stack.extend([skin, interior, skin]);
            }
        }
        stack.extend(outer.iter().rev());
        let thermal = ThermalGrid::new(
            grid,
            &stack,
            materials.len(),
            settings.minimum_thickness_m,
            settings.quadrature(),
        )
        .map_err(|e| ModelError::inconsistent(NAME, e.to_string()))?;
        let panels = map_panels(grid, &thermal, mesh)?;
        let node_average = thermal.structure_average_weights();
        let node_difference = thermal.structure_difference_weights();
        let n = thermal.n_dofs();
        Ok(Self {
            constant_properties: materials.iter().all(has_constant_thermal_properties),
            matrix: BandedMatrix::zeros(n, thermal.bandwidth),
            factored_dt_s: None,
            load: vec![0.0; n],
            capacity: vec![0.0; n],
            iterate: vec![0.0; n],
            solution: vec![0.0; n],
            picard_iterations: 0,
            settings,
            plate: grid.clone(),
            grid: thermal,
            materials,
            panels,
            node_average,
            node_difference,
        })
    }

    /// The surface grid the model is built on.
    pub fn plate_grid(&self) -> &SurfaceGrid {
        &self.plate
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The extruded grid.
    pub fn thermal_grid(&self) -> &ThermalGrid {
        &self.grid
    }

    /// Materials: the structure first, then the outer layers in settings order, then the
    /// interior of a built-up structure.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Where each wetted panel meets the grid.
    pub fn panel_map(&self) -> &PanelMap {
        &self.panels
    }

    /// (level, weight) pairs that average a plate node's temperature over the structure.
    pub fn node_average_weights(&self) -> &[(usize, f64)] {
        &self.node_average
    }

    /// (level, weight) pairs that give a plate node's through-thickness difference of the
    /// structure ([`ThermalGrid::structure_difference_weights`]).
    pub fn node_difference_weights(&self) -> &[(usize, f64)] {
        &self.node_difference
    }

    /// Σ_levels w T(node, level) at every plate node: the structure's mean temperature or
    /// through-thickness difference, as `weights` say.
    fn weighted_levels(&self, weights: &[(usize, f64)], state: &DVector<f64>, out_k: &mut [f64]) {
        let levels = self.grid.n_levels;
        for (node, out) in out_k.iter_mut().enumerate().take(self.grid.n_plate_nodes) {
            *out = weights
                .iter()
                .map(|&(level, w)| w * state[node * levels + level])
                .sum();
        }
    }

    /// Picard iterations of the last step.
    pub fn last_picard_iterations(&self) -> usize {
        self.picard_iterations
    }

    /// Nodal heat loads F = Σ_panels w q A, W, into `load`.
    pub fn panel_loads(&self, flux_w_m2: &[f64], load: &mut [f64]) {
        load.fill(0.0);
        let p = &self.panels;
        for i in 0..p.n_panels() {
            let power = flux_w_m2[i] * p.loaded_area_m2[i];
            for (dof, w) in p.entries(i) {
                load[dof] += w * power;
            }
        }
    }

    /// Heat stored above `reference` in `state`: Σ_i Σ_m ρ_m V_im ∫_{T_ref}^{T_i} c_p dT, J
    /// (trapezoid rule in 1 K steps over the piecewise-linear c_p; exact for linear c_p).
    pub fn stored_energy_j(
        &self,
        state: &DVector<f64>,
        reference_k: f64,
    ) -> Result<f64, ModelError> {
        let nm = self.grid.n_materials;
        let mut total = 0.0;
        for (i, &t) in state.iter().enumerate() {
            for (m, material) in self.materials.iter().enumerate() {
                let v = self.grid.volume_m3[i * nm + m];
                if v > 0.0 {
                    // Round-off below the table's floor (a node held at its initial 293 K
                    // solves to 292.9999999999999 K) counts as the floor, as in the step.
                    let t = crate::clamp_round_off_k(material, t);
                    total += material.density_kg_m3 * v * enthalpy_rise(material, reference_k, t)?;
                }
            }
        }
        Ok(total)
    }

    /// Diagonal heat capacity at the midpoint temperatures ½(Tⁿ + T), J/K.
    fn fill_capacity(&mut self, previous: &[f64]) -> Result<(), ModelError> {
        let nm = self.grid.n_materials;
        for i in 0..self.capacity.len() {
            let t = 0.5 * (previous[i] + self.iterate[i]);
            let mut c = 0.0;
            for (m, material) in self.materials.iter().enumerate() {
                let v = self.grid.volume_m3[i * nm + m];
                if v > 0.0 {
                    let t = crate::clamp_round_off_k(material, t);
                    let cp = material.specific_heat_j_kg_k(t).map_err(material_error)?;
                    c += material.density_kg_m3 * cp * v;
                }
            }
            self.capacity[i] = c;
        }
        Ok(())
    }

    /// A = C/Δt + K(T_iterate) in band order, factorized.
    fn assemble_and_factorize(&mut self, dt_s: f64) -> Result<(), ModelError> {
        self.matrix.clear();
        let band = &self.grid.band_index;
        for (i, &c) in self.capacity.iter().enumerate() {
            self.matrix.add(band[i], band[i], c / dt_s);
        }
        for e in &self.grid.elements {
            let mean = e.dofs.iter().map(|&d| self.iterate[d]).sum::<f64>() / 8.0;
            let material = &self.materials[e.material];
            let k = material
                .conductivity_w_m_k(crate::clamp_round_off_k(material, mean))
                .map_err(material_error)?;
            for a in 0..8 {
                for b in 0..=a {
                    self.matrix.add(
                        band[e.dofs[a]],
                        band[e.dofs[b]],
                        k * e.conduction_m[a * 8 + b],
                    );
                }
            }
        }
        self.matrix.factorize().map_err(|e| {
            ModelError::inconsistent(
                NAME,
                format!(
                    "conduction matrix is not positive definite (pivot {} at row {}); \
                     a zero-volume part of the grid?",
                    e.pivot, e.row
                ),
            )
        })
    }

    fn check_inputs(
        &self,
        state: &DVector<f64>,
        flux_w_m2: &[f64],
        dt_s: f64,
    ) -> Result<(), ModelError> {
        if state.len() != self.grid.n_dofs() {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "state has {} temperatures, the grid has {} nodes",
                    state.len(),
                    self.grid.n_dofs()
                ),
            ));
        }
        if flux_w_m2.len() != self.panels.n_panels() {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{} heat fluxes for {} surface panels",
                    flux_w_m2.len(),
                    self.panels.n_panels()
                ),
            ));
        }
        check_step_inputs(NAME, flux_w_m2, dt_s)?;
        if let Some(i) = state.iter().position(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(ModelError::out_of_range(
                NAME,
                &format!("temperature (K) of node {i}"),
                state[i],
                "finite and > 0",
            ));
        }
        Ok(())
    }
}

/// ∫_{from}^{to} c_p dT of `m`, J/kg: trapezoid rule on at most 1 K sub-steps, exact for c_p
/// linear between table rows.
pub fn enthalpy_rise(m: &Material, from_k: f64, to_k: f64) -> Result<f64, ModelError> {
    let steps = ((to_k - from_k).abs().ceil() as usize).max(1);
    let h = (to_k - from_k) / steps as f64;
    let mut sum = 0.0;
    let mut previous = m.specific_heat_j_kg_k(from_k).map_err(material_error)?;
    for k in 1..=steps {
        let next = m
            .specific_heat_j_kg_k(from_k + h * k as f64)
            .map_err(material_error)?;
        sum += 0.5 * (previous + next) * h;
        previous = next;
    }
    Ok(sum)
}

impl ConductionModel for FullOrder {
    fn name(&self) -> &str {
        NAME
    }

    fn n_states(&self) -> usize {
        self.grid.n_dofs()
    }

    fn n_nodes(&self) -> usize {
        self.grid.n_plate_nodes
    }

    fn n_surface_panels(&self) -> usize {
        self.panels.n_panels()
    }

    fn uniform_state(&self, temperature_k: f64) -> Result<DVector<f64>, ModelError> {
        for m in &self.materials {
            m.thermal_at(crate::clamp_round_off_k(m, temperature_k))
                .map_err(material_error)?;
        }
        Ok(DVector::from_element(self.grid.n_dofs(), temperature_k))
    }

    fn step(
        &mut self,
        state: &mut DVector<f64>,
        surface_heat_flux_w_m2: &[f64],
        dt_s: f64,
    ) -> Result<(), ModelError> {
        self.check_inputs(state, surface_heat_flux_w_m2, dt_s)?;
        let mut load = std::mem::take(&mut self.load);
        self.panel_loads(surface_heat_flux_w_m2, &mut load);
        self.load = load;
        self.iterate.copy_from_slice(state.as_slice());
        let max_iterations = if self.constant_properties {
            1
        } else {
            self.settings.max_picard_iterations
        };
        for iteration in 1..=max_iterations {
            if !(self.constant_properties && self.factored_dt_s == Some(dt_s)) {
                self.fill_capacity(state.as_slice())?;
                self.assemble_and_factorize(dt_s)?;
                self.factored_dt_s = self.constant_properties.then_some(dt_s);
            }
            let band = &self.grid.band_index;
            for i in 0..state.len() {
                self.solution[band[i]] = self.capacity[i] / dt_s * state[i] + self.load[i];
            }
            self.matrix.solve_in_place(&mut self.solution);
            let mut change: f64 = 0.0;
            for i in 0..state.len() {
                let t = self.solution[band[i]];
                change = change.max((t - self.iterate[i]).abs());
                self.iterate[i] = t;
            }
            if !change.is_finite() {
                return Err(ModelError::NonFinite {
                    model: NAME.to_owned(),
                    quantity: "temperature".to_owned(),
                    location: format!(" in Picard iteration {iteration}"),
                });
            }
            if self.constant_properties || change < self.settings.picard_tolerance_k {
                self.picard_iterations = iteration;
                state.as_mut_slice().copy_from_slice(&self.iterate);
                return Ok(());
            }
        }
        Err(ModelError::inconsistent(
            NAME,
            format!(
                "Picard iteration did not converge to {} K in {} iterations (time step {dt_s} s); \
                 reduce the time step or raise max_picard_iterations",
                self.settings.picard_tolerance_k, self.settings.max_picard_iterations
            ),
        ))
    }

    fn surface_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        let p = &self.panels;
        for (i, out) in out_k.iter_mut().enumerate().take(p.n_panels()) {
            *out = p.entries(i).map(|(dof, w)| w * state[dof]).sum();
        }
    }

    fn node_grid(&self) -> Option<&SurfaceGrid> {
        Some(&self.plate)
    }

    /// Solid: T at the structure's lowest level minus T at its highest (levels run lower face
    /// first); built up: the lower skin's mean temperature minus the upper skin's.
    fn node_temperature_differences(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        self.weighted_levels(&self.node_difference, state, out_k);
    }

    fn node_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        self.weighted_levels(&self.node_average, state, out_k);
    }
}
