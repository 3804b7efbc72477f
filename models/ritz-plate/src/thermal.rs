//! Heat-degraded stiffness: the modulus from a node temperature field, the thermal-stress
//! geometric stiffness, and the reduced matrices and thermal generalized forces updated from them.

use super::*;

impl ThermalStiffness for RitzPlate {
    fn temperature_nodes(&self) -> usize {
        self.plate.grid.n_nodes()
    }

    fn set_temperatures(&mut self, node_temperatures_k: &[f64]) -> Result<(), ModelError> {
        self.update_temperatures(node_temperatures_k, None)
    }

    fn set_temperature_field(
        &mut self,
        mean_k: &[f64],
        difference_k: &[f64],
    ) -> Result<(), ModelError> {
        RitzPlate::set_temperature_field(self, mean_k, difference_k)
    }

    fn thermal_generalized_forces(&self) -> Option<&DVector<f64>> {
        Some(RitzPlate::thermal_generalized_forces(self))
    }

    /// The structural grid; the right surface's, so the left surface's temperatures are taken
    /// in the same node order (the mirror image).
    fn temperature_grid(&self) -> Option<&SurfaceGrid> {
        Some(&self.plate.grid)
    }
}

impl RitzPlate {
    /// Updates stiffness and the thermal-moment load from mid-plane node temperatures (K) and
    /// node through-thickness differences ΔT = T(lower face, z = +t/2) − T(upper face) (K,
    /// linear in z; node order of [`RitzPlate::grid`]). [`ThermalStiffness::set_temperatures`] is
    /// this with ΔT = 0. Allocation-free.
    pub fn set_temperature_field(
        &mut self,
        mean_k: &[f64],
        difference_k: &[f64],
    ) -> Result<(), ModelError> {
        self.update_temperatures(mean_k, Some(difference_k))
    }

    /// Element states, membrane solve and reduced update for a temperature field.
    pub(super) fn update_temperatures(
        &mut self,
        mean_k: &[f64],
        difference_k: Option<&[f64]>,
    ) -> Result<(), ModelError> {
        self.plate
            .element_states(mean_k, difference_k, &mut self.states)
            .map_err(model_error)?;
        self.plate
            .membrane_resultants_into(
                &self.states,
                &mut self.membrane_k,
                &mut self.membrane_rhs,
                &mut self.resultants,
            )
            .map_err(model_error)?;
        if let Some(e) = self
            .resultants
            .iter()
            .position(|n| n.iter().any(|v| !v.is_finite()))
        {
            return Err(ModelError::NonFinite {
                model: NAME.to_owned(),
                quantity: "membrane stress resultant".to_owned(),
                location: format!(" in element {e}"),
            });
        }
        self.update_reduced()
    }

    /// Recomputes K_r, root-load matrices, eigen-decomposition and damping from the current
    /// element states and resultants (allocation-free).
    pub(super) fn update_reduced(&mut self) -> Result<(), ModelError> {
        let r = self.reduced.size;
        let rr = r * r;
        let k = self.modal.stiffness.as_mut_slice();
        k.iter_mut().for_each(|v| *v = 0.0);
        for (e, state) in self.states.iter().enumerate() {
            let s = state.stiffness_scale;
            let ke = &self.reduced.stiffness[e * rr..(e + 1) * rr];
            let n = self.resultants[e];
            let g = &self.reduced.geometric[3 * e * rr..(3 * e + 3) * rr];
            for idx in 0..rr {
                k[idx] += s * ke[idx] + n[0] * g[idx] + n[1] * g[rr + idx] + n[2] * g[2 * rr + idx];
            }
        }
        // Exact symmetry for the eigen-solver.
        for i in 0..r {
            for j in (i + 1)..r {
                let avg = 0.5 * (k[i * r + j] + k[j * r + i]);
                k[i * r + j] = avg;
                k[j * r + i] = avg;
            }
        }
        self.root_stiffness.fill(0.0);
        for re in &self.root_elements {
            let s = self.states[re.element].stiffness_scale;
            let n = self.resultants[re.element];
            for idx in 0..6 * r {
                self.root_stiffness.as_mut_slice()[idx] += s * re.stiffness.as_slice()[idx]
                    + n[0] * re.geometric[0].as_slice()[idx]
                    + n[1] * re.geometric[1].as_slice()[idx]
                    + n[2] * re.geometric[2].as_slice()[idx];
            }
        }
        self.thermal_forces.fill(0.0);
        for (e, state) in self.states.iter().enumerate() {
            let scale = state.stiffness_scale * state.thermal_strain_difference;
            if scale != 0.0 {
                let fe = &self.reduced.thermal[e * r..(e + 1) * r];
                for (q, f) in self.thermal_forces.iter_mut().zip(fe) {
                    *q += scale * f;
                }
            }
        }
        self.symmetric_eigen
            .decompose(
                &self.modal.stiffness,
                &mut self.eigenvalues,
                &mut self.eigenvectors,
            )
            .map_err(|e| ModelError::inconsistent(NAME, format!("reduced stiffness: {e}")))?;
        // C = Ψ diag(2 ζ ω) Ψᵀ (M_r = I); a buckled (λ < 0) mode gets none.
        let c = &mut self.modal.damping;
        c.fill(0.0);
        for m in 0..r {
            let lam = self.eigenvalues[m];
            if lam <= 0.0 {
                continue;
            }
            let coef = 2.0 * self.damping_ratio * lam.sqrt();
            for i in 0..r {
                let pi = self.eigenvectors[(i, m)] * coef;
                for j in 0..r {
                    c[(i, j)] += pi * self.eigenvectors[(j, m)];
                }
            }
        }
        Ok(())
    }

    /// Generalized thermal-moment force Q_T = Φᵀ f_T of the latest temperature field (one per
    /// Ritz coordinate; N m per unit modal coordinate): add it to the applied generalized forces,
    /// M_r q̈ + C_r q̇ + K_r q = Q_applied + Q_T. Zero without a through-thickness difference.
    pub fn thermal_generalized_forces(&self) -> &DVector<f64> {
        &self.thermal_forces
    }
}
