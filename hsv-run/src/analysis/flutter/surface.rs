//! One lifting surface alone in the flow with its root fixed: its Ritz equations, static
//! equilibrium and identified linear state matrix (paper Eqs. 4-7).
//!
//! **Equations.** M q̈ + C q̇ + K q = Q_aero(q, q̇) + Q_T with the state x = [q; q̇]: M, C, K the
//! structure's current modal matrices (after its temperature update), Q_T its thermal-moment
//! generalized force, and Q_aero the generalized force of the pressure a named aero model gives
//! on the deformed mesh (vertices + Φ q) with the panels' elastic velocities Φ q̇ (off with
//! [`SurfaceOptions::aero_damping`], the quasi-static aero of classical panel flutter). The
//! pressure is projected on the mode shapes of the reference geometry,
//! Q = −P (p − p∞) ([`ModalProjection`]: the small-displacement assumption of the linear modal
//! structure; the follower rotation of the panels is of order q and is left out). An aero
//! model with memory of the modal motion (a convolution ROM, [`ModalHistoryAero`]) gives Q_aero
//! itself from a modal history owned here: the surface at rest at q for all earlier time, then
//! moving at q̇ (the state has no aerodynamic lag states; exact for ROMs of memoryless sources).
//!
//! **Buckled structures.** When heating has made K alone indefinite (thermal buckling in
//! vacuum) the surface is still analysed: with the aero stiffness the identified A then has a
//! real root in the right half plane (static divergence) unless the flow holds the surface,
//! and paper Eq. 8 counts any root that crosses into the right half plane as the instability.
//! A buckled mode has no modal damping, so the largest real part passes through zero
//! continuously where the stiffness turns indefinite and the sweep can bracket that crossing.
//!
//! **Equilibrium.** x_e = [q0; 0] with K q0 = Q_aero(q0, 0) + Q_T, by Newton's method on
//! r(q) = Q_aero(q, 0) + Q_T − K q with the aero stiffness ∂Q/∂q by central differences.
//!
//! **Identification** (paper Eqs. 6-7). A(:, k) = (f(x_e + Δ_k) − f(x_e − Δ_k)) / 2ε_k with
//! ε_k = 1 % of |x_e,k|, or where that is smaller a small absolute value: a modal displacement
//! that moves the surface by 1e-6 of its size, and that displacement times the mode's natural
//! frequency for a modal velocity (so every perturbation is a small, comparable motion).
//! f is either the state derivative evaluated directly ([`DerivativeMethod::Direct`]) or, as in
//! the paper, the sixth-order forward difference of 7 samples of the surface simulation
//! started at x ([`DerivativeMethod::ForwardDifference`]: classical Runge-Kutta at
//! Δt = 0.05/ω_max, the bound ω_max² ≥ the largest eigenvalue of M⁻¹K from its row sums; the
//! formula's error ~ (ω Δt)⁶ and the integrator's ~ (ω Δt)⁴ are both far below the
//! perturbation's own linearization error).

use hsv_core::aero::{AeroModel, AeroSolution, ModalHistory, ModalHistoryAero, PanelMotion};
use hsv_core::coupling::ModalProjection;
use hsv_core::flow::FlightCondition;
use hsv_core::mesh::{ModeShapes, PanelMesh};
use hsv_core::structure::StructureModel;
use nalgebra::{Cholesky, DMatrix, DVector, Dyn, Vector3};

use super::{FlutterError, check_positive};
use crate::dynamics::Rk4;
use crate::dynamics::linearize::{central_difference_jacobians, forward_difference_derivative};

/// How the state derivative of the identification is obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DerivativeMethod {
    /// f(x) evaluated from the equations of motion.
    Direct,
    /// The paper's: the sixth-order forward difference over 7 steps of the surface simulation.
    ForwardDifference,
}

/// Options of the surface equations and their identification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceOptions {
    /// Whether the aero sees the elastic panel velocities Φ q̇ (aerodynamic damping).
    pub aero_damping: bool,
    /// Relative perturbation of paper Eq. 7 (the paper: 0.01).
    pub relative_perturbation: f64,
    /// Absolute perturbation as a fraction of the surface size (module docs).
    pub absolute_perturbation: f64,
    /// ω_max Δt of the forward-difference simulation.
    pub forward_difference_step: f64,
    /// Newton iterations allowed for the equilibrium.
    pub max_newton_iterations: usize,
}

impl Default for SurfaceOptions {
    fn default() -> Self {
        Self {
            aero_damping: true,
            relative_perturbation: 0.01,
            absolute_perturbation: 1e-6,
            forward_difference_step: 0.05,
            // Near the divergence of a heated surface the equilibrium is large and Newton
            // converges only linearly: 12 iterations stalled on a 2.8 % wedge at Mach 5.89
            // after 10 s at 10 km, 40 converged.
            max_newton_iterations: 40,
        }
    }
}

/// The static equilibrium of the surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Equilibrium {
    /// x_e = [q0; 0].
    pub state: DVector<f64>,
    pub newton_iterations: usize,
    /// |r(q0)| / load scale.
    pub relative_residual: f64,
}

/// An identified state matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct Identification {
    pub method: DerivativeMethod,
    /// A, 2n × 2n.
    pub a: DMatrix<f64>,
    /// The perturbation ε_k of each state.
    pub perturbations: DVector<f64>,
    /// Time step of the forward-difference simulation, s (0 for the direct derivative).
    pub step_s: f64,
}

/// The equations of one surface (module docs). Scratch buffers only; the state is passed in.
pub struct SurfaceDynamics {
    aero: Box<dyn AeroModel>,
    aero_name: String,
    flight: FlightCondition,
    mesh: PanelMesh,
    deformed: PanelMesh,
    shapes: ModeShapes,
    projection: ModalProjection,
    mass: Cholesky<f64, Dyn>,
    mass_matrix: DMatrix<f64>,
    damping: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    thermal_forces: DVector<f64>,
    options: SurfaceOptions,
    /// Largest displacement of each mode on the mesh, m per unit coordinate.
    mode_scale_m: Vec<f64>,
    surface_size_m: f64,
    q: DVector<f64>,
    qd: DVector<f64>,
    rhs: DVector<f64>,
    velocities: Vec<Vector3<f64>>,
    forces: Vec<f64>,
    solution: AeroSolution,
    evaluations: usize,
    /// The modal history of an aero model with memory (module docs); `None` for the others.
    history: Option<ModalHistory>,
    /// Why the structure's own stiffness is not positive definite, when it is not.
    buckled: Option<String>,
}

/// `Some(reason)` when the stiffness of `structure` alone is no longer positive definite
/// (thermal buckling in vacuum); a non-finite frequency is an error.
fn buckling(structure: &dyn StructureModel) -> Result<Option<String>, FlutterError> {
    match structure.natural_frequencies_hz() {
        Ok(_) => Ok(None),
        Err(e @ hsv_core::ModelError::NonFinite { .. }) => {
            Err(FlutterError::model(structure.name(), e))
        }
        Err(e) => Ok(Some(e.to_string())),
    }
}

/// Largest |φ| of each mode over the vertices, m.
fn mode_scales(shapes: &ModeShapes) -> Vec<f64> {
    shapes
        .vertex_displacement
        .column_iter()
        .map(|c| c.iter().fold(0.0_f64, |m, v| m.max(v.abs())))
        .collect()
}

/// A history at rest for an aero model with memory of `n` modes; `None` for the others.
fn rom_history(aero: &mut dyn AeroModel, n: usize) -> Result<Option<ModalHistory>, FlutterError> {
    let name = aero.name().to_owned();
    let Some(rom) = aero.modal_history() else {
        return Ok(None);
    };
    if rom.n_modes() != n {
        return Err(FlutterError::Inconsistent(format!(
            "`{name}` takes {} modes, the structure has {n} (its `structure` and `modes` settings \
             must name the surface's structure and all its modes)",
            rom.n_modes()
        )));
    }
    rom.initial_history(0.0, &DVector::zeros(n))
        .map(Some)
        .map_err(|e| FlutterError::model(&name, e))
}

/// Q_aero of a model with memory at (q, q̇) after rest at q (module docs), on the undeformed
/// mesh; q̇ = 0 without aerodynamic damping.
#[allow(clippy::too_many_arguments)]
fn rom_forces(
    rom: &mut dyn ModalHistoryAero,
    history: &mut ModalHistory,
    mesh: &PanelMesh,
    flight: &FlightCondition,
    q: &DVector<f64>,
    qd: &DVector<f64>,
    aero_damping: bool,
    forces: &mut [f64],
) -> Result<(), hsv_core::ModelError> {
    *history = rom.initial_history(0.0, q)?;
    let still;
    let velocities = if aero_damping {
        qd
    } else {
        still = DVector::zeros(qd.len());
        &still
    };
    rom.evaluate_modal(mesh, flight, history, 0.0, q, velocities, forces, None)
}

impl SurfaceDynamics {
    /// The equations of `structure` (its current matrices and thermal load) in the flow of
    /// `flight`, with the pressures of `aero` on `mesh`. A structure buckled in vacuum is
    /// analysed too (module docs) and says so in [`Self::buckled_in_vacuum`].
    pub fn new(
        mesh: PanelMesh,
        aero: Box<dyn AeroModel>,
        structure: &dyn StructureModel,
        flight: FlightCondition,
        options: SurfaceOptions,
    ) -> Result<Self, FlutterError> {
        check_positive("relative perturbation", options.relative_perturbation)?;
        check_positive("absolute perturbation", options.absolute_perturbation)?;
        check_positive(
            "forward-difference step ω Δt",
            options.forward_difference_step,
        )?;
        let buckled = buckling(structure)?;
        let modal = structure.modal_model();
        let n = modal.n_modes();
        let shapes = structure
            .mode_shapes_on(&mesh)
            .map_err(|e| FlutterError::model(structure.name(), e))?;
        if shapes.n_modes() != n {
            return Err(FlutterError::Inconsistent(format!(
                "`{}` gives {} mode shapes for {n} modes",
                structure.name(),
                shapes.n_modes()
            )));
        }
        let projection = ModalProjection::new(&mesh, &shapes, |_| true)?;
        let mass = Cholesky::new(modal.mass.clone()).ok_or_else(|| {
            FlutterError::Inconsistent(format!(
                "`{}`: the generalized mass is not symmetric positive definite",
                structure.name()
            ))
        })?;
        let thermal_forces = structure
            .thermal_stiffness()
            .and_then(|t| t.thermal_generalized_forces())
            .cloned()
            .unwrap_or_else(|| DVector::zeros(n));
        let (lo, hi) = mesh.bounding_box();
        let n_panels = mesh.panels.len();
        let mut aero = aero;
        let history = rom_history(aero.as_mut(), n)?;
        Ok(Self {
            history,
            buckled,
            aero_name: aero.name().to_owned(),
            aero,
            flight,
            deformed: mesh.clone(),
            mode_scale_m: mode_scales(&shapes),
            surface_size_m: (hi - lo).norm(),
            mesh,
            shapes,
            projection,
            mass,
            mass_matrix: modal.mass.clone(),
            damping: modal.damping.clone(),
            stiffness: modal.stiffness.clone(),
            thermal_forces,
            options,
            q: DVector::zeros(n),
            qd: DVector::zeros(n),
            rhs: DVector::zeros(n),
            velocities: vec![Vector3::zeros(); n_panels],
            forces: vec![0.0; n],
            solution: AeroSolution::default(),
            evaluations: 0,
        })
    }

    /// Number of Ritz coordinates n (the state has 2n entries).
    pub fn n_modes(&self) -> usize {
        self.q.len()
    }

    /// The flight condition.
    pub fn flight(&self) -> &FlightCondition {
        &self.flight
    }

    /// (M, C, K) of the structure as the equations use them.
    pub fn structural_matrices(&self) -> (&DMatrix<f64>, &DMatrix<f64>, &DMatrix<f64>) {
        (&self.mass_matrix, &self.damping, &self.stiffness)
    }

    /// Q_T, the thermal-moment generalized force.
    pub fn thermal_forces(&self) -> &DVector<f64> {
        &self.thermal_forces
    }

    /// Why the structure alone is buckled (its stiffness not positive definite), if it is.
    pub fn buckled_in_vacuum(&self) -> Option<&str> {
        self.buckled.as_deref()
    }

    /// Aero evaluations so far.
    pub fn aero_evaluations(&self) -> usize {
        self.evaluations
    }

    /// The mode shapes on the mesh.
    pub fn shapes(&self) -> &ModeShapes {
        &self.shapes
    }

    /// Q_aero(q, q̇) into `self.forces` (q, q̇ from `self.q`, `self.qd`).
    fn aero_forces(&mut self) -> Result<(), FlutterError> {
        if let (Some(rom), Some(history)) = (self.aero.modal_history(), self.history.as_mut()) {
            return rom_forces(
                rom,
                history,
                &self.mesh,
                &self.flight,
                &self.q,
                &self.qd,
                self.options.aero_damping,
                &mut self.forces,
            )
            .map(|()| self.evaluations += 1)
            .map_err(|e| FlutterError::model(&self.aero_name, e));
        }
        self.shapes.deform(&self.mesh, &self.q, &mut self.deformed);
        let motion = if self.options.aero_damping {
            self.shapes
                .panel_velocities(&self.mesh, &self.qd, &mut self.velocities);
            PanelMotion {
                elastic_velocity_m_s: Some(&self.velocities),
            }
        } else {
            PanelMotion::default()
        };
        self.aero
            .evaluate(&self.deformed, &self.flight, &motion, &mut self.solution)
            .map_err(|e| FlutterError::model(&self.aero_name, e))?;
        self.evaluations += 1;
        self.projection.generalized_forces(
            &self.solution.pressure_pa,
            self.flight.freestream.pressure_pa,
            &mut self.forces,
        )?;
        Ok(())
    }

    fn check_state(&self, x: &DVector<f64>, what: &str) -> Result<(), FlutterError> {
        let n = self.n_modes();
        if x.len() != 2 * n {
            return Err(FlutterError::Inconsistent(format!(
                "{what} has {} entries, the surface has {} states",
                x.len(),
                2 * n
            )));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(FlutterError::InvalidInput {
                quantity: format!("{what} entry {i}"),
                value: x[i],
                allowed: "finite",
            });
        }
        Ok(())
    }

    /// ẋ = f(x) = [q̇; M⁻¹ (Q_aero + Q_T − C q̇ − K q)] into `out`. Allocation-free.
    pub fn derivative(
        &mut self,
        x: &DVector<f64>,
        out: &mut DVector<f64>,
    ) -> Result<(), FlutterError> {
        self.check_state(x, "state")?;
        let n = self.n_modes();
        if out.len() != 2 * n {
            return Err(FlutterError::Inconsistent(format!(
                "derivative buffer has {} entries, expected {}",
                out.len(),
                2 * n
            )));
        }
        self.q.copy_from(&x.rows(0, n));
        self.qd.copy_from(&x.rows(n, n));
        self.aero_forces()?;
        for (r, (f, t)) in self
            .rhs
            .iter_mut()
            .zip(self.forces.iter().zip(self.thermal_forces.iter()))
        {
            *r = f + t;
        }
        self.rhs.gemv(-1.0, &self.damping, &self.qd, 1.0);
        self.rhs.gemv(-1.0, &self.stiffness, &self.q, 1.0);
        self.mass.solve_mut(&mut self.rhs);
        out.rows_mut(0, n).copy_from(&self.qd);
        out.rows_mut(n, n).copy_from(&self.rhs);
        if let Some(i) = out.iter().position(|v| !v.is_finite()) {
            return Err(FlutterError::InvalidInput {
                quantity: format!("state derivative entry {i}"),
                value: out[i],
                allowed: "finite",
            });
        }
        Ok(())
    }

    /// The static residual r(q) = Q_aero(q, 0) + Q_T − K q into `out`.
    fn static_residual(
        &mut self,
        q: &DVector<f64>,
        out: &mut DVector<f64>,
    ) -> Result<(), FlutterError> {
        self.q.copy_from(q);
        self.qd.fill(0.0);
        self.aero_forces()?;
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.forces[i] + self.thermal_forces[i];
        }
        out.gemv(-1.0, &self.stiffness, q, 1.0);
        Ok(())
    }

    /// The absolute perturbation of each state (module docs): a modal displacement moving the
    /// surface by `absolute_perturbation` × its size, and that times ω_k for a modal velocity.
    fn absolute_steps(&self) -> DVector<f64> {
        let n = self.n_modes();
        let target_m = self.options.absolute_perturbation * self.surface_size_m.max(1e-12);
        DVector::from_fn(2 * n, |i, _| {
            let k = i % n;
            let scale = self.mode_scale_m[k];
            let displacement = if scale > 0.0 { target_m / scale } else { 1e-6 };
            if i < n {
                displacement
            } else {
                let omega = (self.stiffness[(k, k)].abs() / self.mass_matrix[(k, k)]).sqrt();
                displacement * omega.max(1.0)
            }
        })
    }

    /// ε_k = max(relative |x_k|, absolute_k) around `x` (paper Eq. 7).
    pub fn perturbations(&self, x: &DVector<f64>) -> DVector<f64> {
        let absolute = self.absolute_steps();
        DVector::from_fn(x.len(), |i, _| {
            (self.options.relative_perturbation * x[i].abs()).max(absolute[i])
        })
    }

    /// The static equilibrium (module docs).
    pub fn equilibrium(&mut self) -> Result<Equilibrium, FlutterError> {
        let n = self.n_modes();
        let mut q = DVector::zeros(n);
        let mut r = DVector::zeros(n);
        let mut plus = DVector::zeros(n);
        let mut minus = DVector::zeros(n);
        let steps = self.absolute_steps();
        // Elastic force of the small reference displacements: the floor of the load scale, so
        // a surface with next to no load (a symmetric section at zero incidence) converges at
        // round-off instead of chasing it.
        let floor = (&self.stiffness * steps.rows(0, n)).norm();
        let mut scale = 0.0;
        let mut relative = f64::INFINITY;
        for iteration in 0..=self.options.max_newton_iterations {
            self.static_residual(&q, &mut r)?;
            // Load scale: the largest of the applied loads and the elastic force.
            scale = self
                .forces
                .iter()
                .map(|v| v * v)
                .sum::<f64>()
                .sqrt()
                .max(self.thermal_forces.norm())
                .max((&self.stiffness * &q).norm())
                .max(floor);
            relative = if scale > 0.0 { r.norm() / scale } else { 0.0 };
            if relative <= 1e-10 || scale == 0.0 {
                let mut state = DVector::zeros(2 * n);
                state.rows_mut(0, n).copy_from(&q);
                return Ok(Equilibrium {
                    state,
                    newton_iterations: iteration,
                    relative_residual: relative,
                });
            }
            if iteration == self.options.max_newton_iterations {
                break;
            }
            // J = ∂r/∂q by central differences.
            let mut jacobian = DMatrix::zeros(n, n);
            let mut qk = q.clone();
            for k in 0..n {
                let eps = (self.options.relative_perturbation * q[k].abs()).max(steps[k]);
                qk[k] = q[k] + eps;
                self.static_residual(&qk, &mut plus)?;
                qk[k] = q[k] - eps;
                self.static_residual(&qk, &mut minus)?;
                qk[k] = q[k];
                let span = (q[k] + eps) - (q[k] - eps);
                jacobian.set_column(k, &((&plus - &minus) / span));
            }
            let Some(step) = jacobian.lu().solve(&r) else {
                break;
            };
            q -= step;
        }
        Err(FlutterError::NoEquilibrium {
            iterations: self.options.max_newton_iterations,
            residual: relative * scale,
            scale,
        })
    }

    /// The state derivative at `x` by the paper's forward difference over 7 samples of the
    /// simulation started at `x` with step `dt_s`, into `out`.
    pub fn simulated_derivative(
        &mut self,
        x: &DVector<f64>,
        dt_s: f64,
        out: &mut DVector<f64>,
    ) -> Result<(), FlutterError> {
        check_positive("forward-difference time step (s)", dt_s)?;
        let mut rk4 = Rk4::new(x.len());
        let mut samples = Vec::with_capacity(7);
        let mut state = x.clone();
        samples.push(state.clone());
        for j in 0..6 {
            let mut f = |_t: f64, s: &DVector<f64>, dx: &mut DVector<f64>| self.derivative(s, dx);
            rk4.step(&mut f, j as f64 * dt_s, dt_s, &mut state)?;
            samples.push(state.clone());
        }
        forward_difference_derivative(&samples, dt_s, out)?;
        Ok(())
    }

    /// Δt of the forward-difference simulation: `forward_difference_step` / ω_max, with
    /// ω_max² the largest row sum of |M⁻¹ K| (Gershgorin: ≥ every eigenvalue).
    pub fn forward_difference_step_s(&self) -> f64 {
        let mut mk = self.stiffness.clone();
        for mut col in mk.column_iter_mut() {
            let mut c = col.clone_owned();
            self.mass.solve_mut(&mut c);
            col.copy_from(&c);
        }
        let bound = mk
            .row_iter()
            .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0_f64, f64::max);
        self.options.forward_difference_step / bound.sqrt().max(1e-3)
    }

    /// A around `equilibrium` by central differences of f (paper Eqs. 6-7).
    pub fn identify(
        &mut self,
        equilibrium: &DVector<f64>,
        method: DerivativeMethod,
    ) -> Result<Identification, FlutterError> {
        self.check_state(equilibrium, "equilibrium state")?;
        let steps = self.perturbations(equilibrium);
        let none = DVector::zeros(0);
        let n_out = equilibrium.len();
        let step_s = match method {
            DerivativeMethod::Direct => 0.0,
            DerivativeMethod::ForwardDifference => self.forward_difference_step_s(),
        };
        let (a, _) = central_difference_jacobians(
            |x: &DVector<f64>, _u: &DVector<f64>, out: &mut DVector<f64>| match method {
                DerivativeMethod::Direct => self.derivative(x, out),
                DerivativeMethod::ForwardDifference => self.simulated_derivative(x, step_s, out),
            },
            equilibrium,
            &none,
            n_out,
            &steps,
            &none,
        )?;
        Ok(Identification {
            method,
            a,
            perturbations: steps,
            step_s,
        })
    }
}
