//! The body-surface interface: the surfaces' root loads by force summation, the state
//! derivative with the interface closed by the configured fixed-point acceleration, and the
//! guesses and residuals the staggered scheme and the restart carry.

use super::*;

impl PartitionedVehicle {
    /// The coupling iteration's guesses (each surface's q̈ and the last Aitken step), which the
    /// next [`Self::derivative`] starts from.
    pub fn coupling_guess(&self) -> CouplingGuess {
        CouplingGuess {
            q_ddot: self.memory.q_ddot.clone(),
            body_q_ddot: self.memory.body_q_ddot.clone(),
        }
    }

    /// Starts the next coupling iteration from `guess` (a linearization restores one guess
    /// before every evaluation, so its derivative is a function of its arguments alone).
    pub fn set_coupling_guess(&mut self, guess: &CouplingGuess) -> Result<(), VehicleError> {
        let fits = |a: &[DVector<f64>], b: &[DVector<f64>]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.len() == y.len())
        };
        if !(fits(&guess.q_ddot, &self.memory.q_ddot)
            && guess.body_q_ddot.len() == self.memory.body_q_ddot.len())
        {
            return Err(VehicleError::Input(
                "a coupling guess of another vehicle (surface mode counts differ)".to_owned(),
            ));
        }
        self.memory.q_ddot.clone_from(&guess.q_ddot);
        self.memory.body_q_ddot.copy_from(&guess.body_q_ddot);
        Ok(())
    }

    /// Length of the interface vector of the staggered scheme ([`crate::vehicle::staggered`]): every
    /// surface's q̈, then the body's η̈.
    pub fn interface_len(&self) -> usize {
        self.memory.q_ddot.iter().map(|q| q.len()).sum::<usize>() + self.memory.body_q_ddot.len()
    }

    /// The interface unknowns the next derivative starts from, into `out`
    /// ([`Self::interface_len`] entries).
    pub fn interface_guess(&self, out: &mut [f64]) {
        gather(
            out,
            self.memory
                .q_ddot
                .iter()
                .chain(std::iter::once(&self.memory.body_q_ddot)),
        );
    }

    /// Sets the interface unknowns from `guess` ([`Self::interface_len`] entries).
    pub fn set_interface_guess(&mut self, guess: &[f64]) {
        scatter(
            guess,
            self.memory
                .q_ddot
                .iter_mut()
                .chain(std::iter::once(&mut self.memory.body_q_ddot)),
        );
    }

    /// One evaluation of the staggered scheme at time `time_s`: the regions' loads at `state`,
    /// then each region once with the other side's interface data `guess` (the previous
    /// sub-iteration's, at this stage), no fixed point; the interface the regions produce goes
    /// to `produced`.
    pub fn staggered_derivative(
        &mut self,
        (step, time_s): (&OpenStep, f64),
        state: &VehicleState,
        controls: &FlightControls,
        guess: &[f64],
        produced: &mut [f64],
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        self.memory.time_s = time_s;
        let flight = self.flight(state)?;
        self.region_loads(state, controls, &flight, step.reads_publications)?;
        self.set_interface_guess(guess);
        let body_without_roots = self.loads.body;
        self.add_root_loads(state, &body_without_roots)?;
        self.loads
            .body_modal_acceleration
            .copy_from(&self.memory.body_q_ddot);
        self.dynamics.derivative(state, &self.loads, out)?;
        gather(
            produced,
            out.surface_modes
                .iter()
                .map(|m| &m.q_ddot)
                .chain(std::iter::once(&out.body_modes.q_ddot)),
        );
        Ok(())
    }

    /// The largest change of an interface displacement between states `a` and `b`, m: the
    /// body's elastic translation at each pivot and each surface's deflection at its mesh
    /// vertices (the staggered scheme's residual, paper Table 3's R_tol).
    pub fn interface_displacement_change_m(&self, a: &VehicleState, b: &VehicleState) -> f64 {
        let mut worst: f64 = 0.0;
        for (i, s) in self.surfaces.iter().enumerate() {
            let mut pivot = Vector3::zeros();
            for (k, c) in s.body_modes_at_pivot.column_iter().enumerate() {
                let dq = a.body_modes.q[k] - b.body_modes.q[k];
                pivot += Vector3::new(c[0], c[1], c[2]) * dq;
            }
            worst = worst.max(pivot.norm());
            let (qa, qb) = (&a.surface_modes[i].q, &b.surface_modes[i].q);
            let d = &s.shapes.vertex_displacement;
            for v in 0..d.nrows() / 3 {
                let mut change = Vector3::zeros();
                for k in 0..d.ncols() {
                    let dq = qa[k] - qb[k];
                    change +=
                        Vector3::new(d[(3 * v, k)], d[(3 * v + 1, k)], d[(3 * v + 2, k)]) * dq;
                }
                worst = worst.max(change.norm());
            }
        }
        worst
    }

    /// Records a staggered step's sub-iterations and final interface residual (m) as the
    /// coupling report.
    pub fn set_staggered_report(&mut self, sub_iterations: usize, residual_m: f64) {
        self.memory.coupling = CouplingReport {
            iterations: sub_iterations,
            residual: residual_m,
        };
    }

    /// The staggered scheme's settings, None when every stage closes the interface (implicit).
    pub fn staggered(&self) -> Option<crate::vehicle::staggered::StaggeredSettings> {
        self.staggered
    }

    /// Flies the staggered scheme with `settings`, or the implicit one with None. Trim and
    /// linearization always close the interface (a steady state has no step to stagger).
    pub fn set_staggered(
        &mut self,
        settings: Option<crate::vehicle::staggered::StaggeredSettings>,
    ) {
        self.staggered = settings;
    }

    /// Accelerates the coupling fixed points as `[coupling]` says (`acceleration`,
    /// `relaxation`, `relaxation_bounds`).
    pub fn set_acceleration(&mut self, config: &CouplingConfig) {
        self.acceleration = hsv_core::acceleration::acceleration(config);
        self.acceleration_config = *config;
    }

    /// A fresh acceleration of the configured kind, for a fixed point of the caller's (the
    /// staggered step's).
    pub fn new_acceleration(&self) -> Box<dyn Acceleration> {
        hsv_core::acceleration::acceleration(&self.acceleration_config)
    }

    /// How the coupling iteration converges.
    pub fn coupling_settings(&self) -> CouplingSettings {
        self.settings
    }

    /// Sets how the coupling iteration converges (a linearization tightens it).
    pub fn set_coupling_settings(&mut self, settings: CouplingSettings) {
        self.settings = settings;
    }

    /// The surfaces' root loads on the body for the current q̈ guess, added to the body loads
    /// about the centre of mass; each surface's relative root-force change goes to its
    /// interface residual, and the largest is returned.
    pub(super) fn add_root_loads(
        &mut self,
        state: &VehicleState,
        body_without_roots: &Loads,
    ) -> Result<f64, VehicleError> {
        let cg = self.mass.center_of_mass_m;
        let mut total = *body_without_roots;
        let mut aero = self.aero_loads;
        let mut change: f64 = 0.0;
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            let err = model_error(&s.name);
            let read = &self.surface_reads[i];
            let (rotation, applied) = (read.elevon_rotation, read.applied_about_pivot);
            let modes = &state.surface_modes[i];
            let root = s
                .structure
                .root_loads()
                .ok_or_else(|| err(ModelError::inconsistent("coupling", "no root loads")))?
                .root_loads(
                    &modes.q,
                    &modes.q_dot,
                    &self.memory.q_ddot[i],
                    &read.applied_surface_frame,
                )
                .map_err(&err)?;
            let force = rotation * root.force_n;
            let moment = rotation * root.moment_nm;
            let last = &mut self.memory.root_force_n[i];
            let scale = force.norm().max(last.norm()).max(1.0);
            let surface_change = (force - *last).norm() / scale;
            self.interface_residuals[i] = surface_change;
            change = change.max(surface_change);
            *last = force;
            self.loads.surface_root_loads[i] = Loads {
                force_n: force,
                moment_nm: moment,
            };
            aero = aero
                + Loads {
                    force_n: applied.force_n,
                    moment_nm: applied.moment_nm + (s.pivot_m - cg).cross(&applied.force_n),
                };
            total = total
                + Loads {
                    force_n: force,
                    moment_nm: moment + (s.pivot_m - cg).cross(&force),
                };
        }
        self.loads.body = total;
        self.aero_with_surfaces = aero;
        Ok(change)
    }

    /// The derivative of a Runge-Kutta stage of the open `step` at time `time_s`: as
    /// [`Self::derivative_at`], with each region that runs at its own rate read from its
    /// publications (module [`crate::vehicle::region_rate`]).
    pub fn stage_derivative(
        &mut self,
        step: &OpenStep,
        time_s: f64,
        state: &VehicleState,
        controls: &FlightControls,
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        self.memory.time_s = time_s;
        self.coupled_derivative(state, controls, step.reads_publications, out)
    }

    /// The state derivative at time `time_s` (the time models with memory read their history up
    /// to and the wind field is sampled at), `state` and `controls`, into `out`, every region
    /// evaluated ([`Self::derivative`] at that time).
    pub fn derivative_at(
        &mut self,
        time_s: f64,
        state: &VehicleState,
        controls: &FlightControls,
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        self.memory.time_s = time_s;
        self.derivative(state, controls, out)
    }

    /// The state derivative at `state` under `controls` into `out` (buffers from
    /// `dynamics().zero_derivative()`), with the body-surface coupling converged (module docs),
    /// at the vehicle's time (its last step's, or trim's t = 0).
    pub fn derivative(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        self.coupled_derivative(state, controls, false, out)
    }

    /// The regions' loads at `state` (those at their own rates read from their publications
    /// when `reads_publications`), then the interface closed on them.
    fn coupled_derivative(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        reads_publications: bool,
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        let flight = self.flight(state)?;
        self.region_loads(state, controls, &flight, reads_publications)?;
        self.close_interface(state, out)
    }

    /// The body-surface interface closed on the region loads of the last evaluation: the
    /// fixed point of (q̈, η̈) with Aitken's relaxation (module docs), the derivative into `out`.
    pub(super) fn close_interface(
        &mut self,
        state: &VehicleState,
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        let body_without_roots = self.loads.body;
        let n_surfaces = self.surfaces.len();
        let mut residual = f64::INFINITY;
        self.acceleration.reset();
        for iteration in 1..=self.settings.max_iterations.max(1) {
            residual = self.add_root_loads(state, &body_without_roots)?;
            self.loads
                .body_modal_acceleration
                .copy_from(&self.memory.body_q_ddot);
            self.dynamics.derivative(state, &self.loads, out)?;
            // The body's side of the interface: η̈ against its iterate, relative to the η̈ that
            // moves a pivot by 1 g.
            let body_change = out
                .body_modes
                .q_ddot
                .iter()
                .zip(self.memory.body_q_ddot.iter())
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
                / self.body_q_ddot_scale;
            if let Some(body) = self.interface_residuals.last_mut() {
                *body = body_change;
            }
            residual = residual.max(body_change);
            if n_surfaces == 0 || (iteration > 1 && residual <= self.settings.tolerance) {
                self.memory.coupling = CouplingReport {
                    iterations: iteration,
                    residual,
                };
                return Ok(());
            }
            // The (q̈, η̈) update, accelerated (`[coupling] acceleration`; both are
            // mass-normalized modal accelerations, so one inner product weighs them alike).
            gather(
                &mut self.iterate,
                self.memory
                    .q_ddot
                    .iter()
                    .chain(std::iter::once(&self.memory.body_q_ddot)),
            );
            gather(
                &mut self.produced,
                out.surface_modes
                    .iter()
                    .map(|m| &m.q_ddot)
                    .chain(std::iter::once(&out.body_modes.q_ddot)),
            );
            self.acceleration.update(&mut self.iterate, &self.produced);
            scatter(
                &self.iterate,
                self.memory
                    .q_ddot
                    .iter_mut()
                    .chain(std::iter::once(&mut self.memory.body_q_ddot)),
            );
        }
        self.memory.coupling = CouplingReport {
            iterations: self.settings.max_iterations,
            residual,
        };
        Err(VehicleError::Coupling {
            iterations: self.settings.max_iterations,
            interfaces: self.interface_names().join(", "),
            residuals: self.interface_residuals.clone(),
            tolerance: self.settings.tolerance,
        })
    }
}
