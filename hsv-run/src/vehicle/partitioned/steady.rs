//! Steady flight of the partitioned vehicle: the in-vacuo modes, the elastic equilibrium at a
//! flight condition (`settle`), level flight, and the trim's [`SteadyFlight`] interface.

use super::*;
use hsv_core::acceleration::{Aitken, ConstantRelaxation};

/// The clamp on Aitken's factor in [`PartitionedVehicle::settle`]: from strong under-relaxation
/// (aero stiffening) to the over-relaxation a slowly converging equilibrium takes.
const SETTLE_AITKEN_BOUNDS: (f64, f64) = (0.05, 2.0);

impl crate::vehicle::rigid::SteadyFlight for PartitionedVehicle {
    fn steady_accelerations(
        &mut self,
        mach: f64,
        altitude_m: f64,
        c: &crate::vehicle::rigid::Controls,
    ) -> Result<
        (
            crate::vehicle::rigid::Accelerations,
            crate::vehicle::rigid::RigidLoads,
        ),
        ModelError,
    > {
        let controls = FlightControls {
            elevon: ElevonCommand {
                symmetric_rad: c.elevon_rad,
                differential_rad: 0.0,
            },
            fuel_equivalence_ratio: c.fuel_equivalence_ratio,
        };
        let (state, out) = self
            .steady_flight_state(
                mach,
                altitude_m,
                c.alpha_rad,
                c.flight_path_angle_rad,
                &controls,
            )
            .map_err(|e| ModelError::inconsistent("flexible vehicle", e.to_string()))?;
        self.trim_modes = state.body_modes.q.iter().copied().collect();
        let a = out.rigid.acceleration_body_m_s2;
        let wind =
            hsv_core::frames::wind_axis_forces(&self.aero_with_surfaces.force_n, c.alpha_rad, 0.0);
        let loads = crate::vehicle::rigid::RigidLoads {
            total: self.loads.body,
            drag_n: wind.drag_n,
            thrust_n: self
                .engine
                .as_ref()
                .map_or(0.0, |e| e.solution.loads.force_n.x),
            engine_status: self
                .engine
                .as_ref()
                .map_or_else(Default::default, |e| e.solution.status),
            ..Default::default()
        };
        Ok((
            crate::vehicle::rigid::Accelerations {
                u_dot_m_s2: a.x,
                w_dot_m_s2: a.z,
                q_dot_rad_s2: out.rigid.angular_acceleration_body_rad_s2.y,
            },
            loads,
        ))
    }

    fn mass_kg(&self) -> f64 {
        self.mass.mass_kg
    }

    fn gas(&self) -> PerfectGas {
        self.gas
    }

    fn powered(&self) -> bool {
        self.engine.is_some()
    }

    fn modal_amplitudes(&self) -> Vec<(String, f64)> {
        let names = &self.body_mode_names;
        names
            .iter()
            .cloned()
            .zip(self.trim_modes.iter().copied())
            .collect()
    }
}

impl PartitionedVehicle {
    /// The assembled structure's in-vacuo modes (no aero, engine or gravity load; the vehicle
    /// free in space): the elastic accelerations ẍ = −M̃⁻¹ K x of the partitioned equations with
    /// the interface closed, column by column for unit modal coordinates, give the condensed
    /// mass M̃ = K (M̃⁻¹ K)⁻¹ (the rigid motion eliminated), and K v = ω² M̃ v its modes. The
    /// surfaces are undeflected and at their current stiffness. Leaves the flight's coupling
    /// guess and settings as it found them. Allocates (an analysis, not the time loop).
    pub fn in_vacuo_modes(&mut self) -> Result<InVacuoModes, VehicleError> {
        let guess = self.coupling_guess();
        let settings = self.settings;
        // Ten times the linearization's tolerance: with many body modes the fixed point stalls
        // near 1e-12 in rounding; the condensed mass stays symmetric to ~1e-9 at 1e-11.
        self.settings = CouplingSettings {
            tolerance: 10.0 * LINEARIZATION_TOLERANCE,
            max_iterations: 400,
        };
        let result = self.in_vacuo_modes_inner();
        self.settings = settings;
        self.set_coupling_guess(&guess)?;
        result
    }

    pub(super) fn in_vacuo_modes_inner(&mut self) -> Result<InVacuoModes, VehicleError> {
        let zero = self.dynamics.zero_loads();
        self.loads = zero;
        self.aero_loads = Loads::default();
        self.surface_reads.fill(SurfaceRead::default());
        let base = self.dynamics.zero_state();
        let n_body = base.body_modes.n_modes();
        let sizes: Vec<usize> = std::iter::once(n_body)
            .chain(base.surface_modes.iter().map(|m| m.n_modes()))
            .collect();
        let n: usize = sizes.iter().sum();
        let mut stiffness = nalgebra::DMatrix::zeros(n, n);
        let (_, _, k_body) = self.dynamics.body_modes().matrices();
        stiffness
            .view_mut((0, 0), (n_body, n_body))
            .copy_from(k_body);
        let mut start = n_body;
        for s in &self.surfaces {
            let k = &s.structure.modal_model().stiffness;
            stiffness
                .view_mut((start, start), (k.nrows(), k.ncols()))
                .copy_from(k);
            start += k.nrows();
        }
        // D = M̃⁻¹ K, column j from the accelerations at coordinate j = ±1: central differences
        // cancel the quadratic terms (the surfaces' pivot moved by the body's modes turning
        // with the rigid body, α × d), leaving the linear structure.
        let mut flexibility_rate = nalgebra::DMatrix::zeros(n, n);
        let mut out = self.dynamics.zero_derivative();
        for j in 0..n {
            for sign in [1.0, -1.0] {
                let mut state = base.clone();
                set_elastic_coordinate(&mut state, j, sign);
                // close_interface adds the root loads to the body's: each column starts unloaded.
                self.loads.body = Loads::default();
                self.close_interface(&state, &mut out)?;
                for i in 0..n {
                    flexibility_rate[(i, j)] -= 0.5 * sign * elastic_acceleration(&out, n_body, i);
                }
            }
        }
        let inverse = flexibility_rate.clone().try_inverse().ok_or_else(|| {
            VehicleError::Input("in-vacuo modes: the coupled accelerations are singular".into())
        })?;
        let mass = &stiffness * inverse;
        let scale = mass.amax().max(f64::MIN_POSITIVE);
        let mass_asymmetry = (&mass - mass.transpose()).amax() / scale;
        let pairs = hsv_core::linalg::generalized_symmetric_eigen(&stiffness, &mass, n)
            .map_err(|e| VehicleError::Input(format!("in-vacuo modes: {e}")))?;
        let mut names = vec!["main_body".to_owned()];
        names.extend(self.surfaces.iter().map(|s| s.name.clone()));
        let modes = (0..pairs.values.len())
            .map(|m| {
                let v = pairs.vectors.column(m);
                let total = (v.transpose() * &stiffness * v)[(0, 0)];
                let mut start = 0;
                let shares = sizes
                    .iter()
                    .map(|&len| {
                        let block = v.rows(start, len);
                        let k = stiffness.view((start, start), (len, len));
                        start += len;
                        (block.transpose() * k * block)[(0, 0)] / total
                    })
                    .collect();
                InVacuoMode {
                    frequency_hz: pairs.values[m].max(0.0).sqrt() / std::f64::consts::TAU,
                    strain_energy_shares: shares,
                }
            })
            .collect();
        Ok(InVacuoModes {
            regions: names,
            modes,
            mass_asymmetry,
        })
    }

    /// Brings the modal coordinates of the body and the surfaces to static equilibrium at the
    /// state's rigid motion (q̇ = 0): q ← q + ω K⁻¹ M q̈ until every modal acceleration is below
    /// `tolerance` (1/s²), which includes aero, engine, gravity and inertial relief through the
    /// root motion. Returns the iterations. Allocates (trim and start-up only).
    ///
    /// First with Aitken's Δ² relaxation from ω = 1 (the plain fixed point q ← K⁻¹ F(q) with the
    /// secant factor of the last two residuals, Küttler & Wall 2008: the trim's elastic
    /// equilibria converge in about half the iterations); when that fails, again from the same
    /// start at constant ω = 1, 1/2 then 1/4. With J = K⁻¹ ∂F/∂q the relaxed iteration's
    /// factors are 1 − ω (1 − λ(J)): aero loads that stiffen the structure strongly (λ < −1)
    /// make the plain iteration overshoot and diverge while a relaxed one converges; λ > 1 is
    /// static divergence, and no relaxation converges (the plain iteration's error is returned).
    pub fn settle(
        &mut self,
        state: &mut VehicleState,
        controls: &FlightControls,
        tolerance: f64,
        max_iterations: usize,
        out: &mut VehicleDerivative,
    ) -> Result<usize, VehicleError> {
        let start = state.clone();
        let mut aitken = Aitken::new(1.0, SETTLE_AITKEN_BOUNDS);
        if let Ok(iterations) =
            self.settle_relaxed(state, controls, tolerance, max_iterations, &mut aitken, out)
        {
            return Ok(iterations);
        }
        state.clone_from(&start);
        let plain = self.settle_relaxed(
            state,
            controls,
            tolerance,
            max_iterations,
            &mut ConstantRelaxation { omega: 1.0 },
            out,
        );
        let Err(plain_error) = plain else {
            return plain;
        };
        for omega in [0.5, 0.25] {
            state.clone_from(&start);
            if let Ok(iterations) = self.settle_relaxed(
                state,
                controls,
                tolerance,
                max_iterations,
                &mut ConstantRelaxation { omega },
                out,
            ) {
                return Ok(iterations);
            }
        }
        state.clone_from(&start);
        Err(plain_error)
    }

    /// [`Self::settle`] with one relaxation of the update q ← q + ω K⁻¹ M q̈.
    pub(super) fn settle_relaxed(
        &mut self,
        state: &mut VehicleState,
        controls: &FlightControls,
        tolerance: f64,
        max_iterations: usize,
        relaxation: &mut dyn Acceleration,
        out: &mut VehicleDerivative,
    ) -> Result<usize, VehicleError> {
        let body_k_m = {
            let (m, _, k) = self.dynamics.body_modes().matrices();
            k.clone().lu().solve(m)
        };
        let surface_k_m: Vec<Option<nalgebra::DMatrix<f64>>> = self
            .surfaces
            .iter()
            .map(|s| {
                let modal = s.structure.modal_model();
                modal.stiffness.clone().lu().solve(&modal.mass)
            })
            .collect();
        state.body_modes.q_dot.fill(0.0);
        for m in &mut state.surface_modes {
            m.q_dot.fill(0.0);
        }
        relaxation.reset();
        let (mut iterate, mut produced) = (Vec::new(), Vec::new());
        for iteration in 1..=max_iterations.max(1) {
            self.derivative(state, controls, out)?;
            let mut largest: f64 = out.body_modes.q_ddot.amax();
            for rate in &out.surface_modes {
                largest = largest.max(rate.q_ddot.amax());
            }
            if largest <= tolerance {
                return Ok(iteration);
            }
            // The fixed-point map's output G(q) = q + K⁻¹ M q̈ beside q, both flat, for the
            // relaxation to combine.
            iterate.clear();
            produced.clear();
            let mut push = |q: &DVector<f64>, step: Option<DVector<f64>>| {
                iterate.extend(q.iter());
                match step {
                    Some(step) => produced.extend(q.iter().zip(step.iter()).map(|(a, b)| a + b)),
                    None => produced.extend(q.iter()),
                }
            };
            push(
                &state.body_modes.q,
                body_k_m.as_ref().map(|km| km * &out.body_modes.q_ddot),
            );
            for (i, km) in surface_k_m.iter().enumerate() {
                push(
                    &state.surface_modes[i].q,
                    km.as_ref().map(|km| km * &out.surface_modes[i].q_ddot),
                );
            }
            relaxation.update(&mut iterate, &produced);
            scatter(
                &iterate,
                std::iter::once(&mut state.body_modes.q)
                    .chain(state.surface_modes.iter_mut().map(|m| &mut m.q)),
            );
        }
        Err(VehicleError::Model {
            region: "vehicle".to_owned(),
            source: ModelError::inconsistent(
                "static elastic equilibrium",
                format!(
                    "modal accelerations still above {tolerance} 1/s^2 after {max_iterations} \
                     iterations (a surface near buckling or divergence?)"
                ),
            ),
        })
    }

    /// The state of steady level flight at `mach`, `altitude_m` and `alpha_rad` with the modes
    /// at static equilibrium under `controls`.
    pub fn level_flight_state(
        &mut self,
        mach: f64,
        altitude_m: f64,
        alpha_rad: f64,
        controls: &FlightControls,
    ) -> Result<(VehicleState, VehicleDerivative), VehicleError> {
        self.steady_flight_state(mach, altitude_m, alpha_rad, 0.0, controls)
    }

    /// [`Self::level_flight_state`] on a path `flight_path_angle_rad` above the horizon (a
    /// glide: γ < 0).
    pub fn steady_flight_state(
        &mut self,
        mach: f64,
        altitude_m: f64,
        alpha_rad: f64,
        flight_path_angle_rad: f64,
        controls: &FlightControls,
    ) -> Result<(VehicleState, VehicleDerivative), VehicleError> {
        let airspeed_m_s = Freestream::standard(mach, altitude_m, self.gas)
            .map_err(model_error("main_body"))?
            .velocity_m_s;
        // Start from the last equilibrium: trim evaluates nearby controls one after another.
        let mut state = self
            .warm_start
            .take()
            .unwrap_or_else(|| self.dynamics.zero_state());
        state.rigid = self.dynamics.rigid_body().steady_flight(
            altitude_m,
            airspeed_m_s,
            alpha_rad,
            flight_path_angle_rad,
        );
        let mut out = self.dynamics.zero_derivative();
        self.settle(&mut state, controls, 1e-6, 200, &mut out)?;
        self.warm_start = Some(state.clone());
        Ok((state, out))
    }
}
