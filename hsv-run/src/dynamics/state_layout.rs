//! The flat state vector's layout: where each part of a [`VehicleState`] sits in the vector
//! the integrator and the linearization work on (quaternion or 3-2-1 Euler attitude), packing
//! and unpacking a state and its derivative, and each entry's name and flight-dynamics role.

use hsv_core::frames;
use nalgebra::{DVector, Quaternion, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::equations_of_motion::{VehicleDerivative, VehicleDynamics, VehicleState};
use super::flight_modes::StateRole;
use super::modal::{ModalRate, ModalState};
use super::{DynamicsError, check_finite, check_len};

/// How the attitude is stored in the flat state vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AttitudeCoordinates {
    /// (q_w, q_x, q_y, q_z): for time integration (no singularity); renormalized on unpacking
    /// and by [`StateLayout::normalize_attitude`] after each step.
    Quaternion,
    /// (φ, θ, ψ): for linear models (minimal, unconstrained); singular at θ = ±90°.
    Euler321,
}

impl AttitudeCoordinates {
    pub fn n_coordinates(self) -> usize {
        match self {
            AttitudeCoordinates::Quaternion => 4,
            AttitudeCoordinates::Euler321 => 3,
        }
    }
}

/// The flat state vector: [north, east, down (m); attitude; u, v, w (m/s); p, q, r (rad/s);
/// body η; body η̇; for each surface: ξ; ξ̇].
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct StateLayout {
    pub attitude: AttitudeCoordinates,
    pub n_body_modes: usize,
    pub n_surface_modes: Vec<usize>,
}

impl VehicleDynamics {
    /// The flat state-vector layout of this vehicle.
    pub fn layout(&self, attitude: AttitudeCoordinates) -> StateLayout {
        StateLayout {
            attitude,
            n_body_modes: self.body_modes().n_modes(),
            n_surface_modes: self
                .surface_modal_models()
                .map(|(modal, _)| modal.n_modes())
                .collect(),
        }
    }

    /// Each lifting surface's structural equations as a linear block of the flat state
    /// (generator at assembly), for [`ExponentialRk4`](super::ExponentialRk4): the stiff Ritz
    /// vectors are then propagated exactly and the heating's stiffness change, the aero, the
    /// root motion and the coupling stay in the explicit remainder.
    pub fn surface_linear_blocks(&self, layout: &StateLayout) -> Vec<super::LinearBlock> {
        self.surface_modal_models()
            .enumerate()
            .map(|(i, (_, generator))| super::LinearBlock {
                start: layout.surface_modes(i),
                generator: generator.clone(),
            })
            .collect()
    }
}

impl StateLayout {
    /// Index of the first attitude entry.
    pub const ATTITUDE: usize = 3;

    /// Index of u (then v, w).
    pub fn velocity(&self) -> usize {
        Self::ATTITUDE + self.attitude.n_coordinates()
    }

    /// Index of p (then q, r).
    pub fn angular_velocity(&self) -> usize {
        self.velocity() + 3
    }

    /// Index of the body's first modal coordinate (its rates follow the coordinates).
    pub fn body_modes(&self) -> usize {
        self.angular_velocity() + 3
    }

    /// Index of surface `i`'s first Ritz coordinate (its rates follow the coordinates).
    pub fn surface_modes(&self, i: usize) -> usize {
        self.body_modes()
            + 2 * self.n_body_modes
            + 2 * self.n_surface_modes[..i.min(self.n_surface_modes.len())]
                .iter()
                .sum::<usize>()
    }

    pub fn len(&self) -> usize {
        self.surface_modes(self.n_surface_modes.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A name with its unit for every entry (CSV headers, linear-model labels).
    pub fn names(&self) -> Vec<String> {
        let mut names: Vec<String> = ["north_m", "east_m", "down_m"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        match self.attitude {
            AttitudeCoordinates::Quaternion => {
                names.extend(["q_w", "q_x", "q_y", "q_z"].map(String::from))
            }
            AttitudeCoordinates::Euler321 => {
                names.extend(["roll_rad", "pitch_rad", "yaw_rad"].map(String::from))
            }
        }
        names
            .extend(["u_m_s", "v_m_s", "w_m_s", "p_rad_s", "q_rad_s", "r_rad_s"].map(String::from));
        let mut modes = |prefix: &str, n: usize| {
            names.extend((1..=n).map(|k| format!("{prefix}_eta_{k}")));
            names.extend((1..=n).map(|k| format!("{prefix}_eta_dot_{k}_per_s")));
        };
        modes("body", self.n_body_modes);
        for (i, &n) in self.n_surface_modes.iter().enumerate() {
            modes(&format!("surface_{}", i + 1), n);
        }
        names
    }

    /// The flight-dynamics role of every entry, for naming eigenmodes
    /// ([`super::flight_modes::flight_modes`]). Structural entries are numbered across the body
    /// and the surfaces in layout order.
    pub fn roles(&self) -> Vec<StateRole> {
        let mut roles = vec![
            StateRole::Position,
            StateRole::Position,
            StateRole::Altitude,
        ];
        match self.attitude {
            AttitudeCoordinates::Quaternion => roles.extend([StateRole::Other; 4]),
            AttitudeCoordinates::Euler321 => {
                roles.extend([StateRole::Roll, StateRole::Pitch, StateRole::Heading])
            }
        }
        roles.extend([
            StateRole::ForwardSpeed,
            StateRole::SideSpeed,
            StateRole::NormalSpeed,
            StateRole::RollRate,
            StateRole::PitchRate,
            StateRole::YawRate,
        ]);
        let mut mode = 0;
        for n in std::iter::once(self.n_body_modes).chain(self.n_surface_modes.iter().copied()) {
            roles.extend((0..n).map(|k| StateRole::Structural { mode: mode + k }));
            roles.extend((0..n).map(|k| StateRole::StructuralRate { mode: mode + k }));
            mode += n;
        }
        roles
    }

    fn check_state(&self, state: &VehicleState) -> Result<(), DynamicsError> {
        check_len(
            || "body modal coordinates".into(),
            self.n_body_modes,
            state.body_modes.q.len(),
        )?;
        check_len(
            || "body modal velocities".into(),
            self.n_body_modes,
            state.body_modes.q_dot.len(),
        )?;
        check_len(
            || "surface modal states".into(),
            self.n_surface_modes.len(),
            state.surface_modes.len(),
        )?;
        for (i, (&n, s)) in self
            .n_surface_modes
            .iter()
            .zip(&state.surface_modes)
            .enumerate()
        {
            check_len(
                || format!("surface {} Ritz coordinates", i + 1),
                n,
                s.q.len(),
            )?;
            check_len(
                || format!("surface {} Ritz velocities", i + 1),
                n,
                s.q_dot.len(),
            )?;
        }
        Ok(())
    }

    /// Writes `state` into `x` (length [`Self::len`]). No allocation.
    pub fn pack(&self, state: &VehicleState, x: &mut DVector<f64>) -> Result<(), DynamicsError> {
        self.check_state(state)?;
        check_len(|| "state vector".into(), self.len(), x.len())?;
        let r = &state.rigid;
        x.fixed_rows_mut::<3>(0).copy_from(&r.position_ned_m);
        let a = Self::ATTITUDE;
        match self.attitude {
            AttitudeCoordinates::Quaternion => {
                let q = r.attitude.quaternion();
                x[a] = q.w;
                x[a + 1] = q.i;
                x[a + 2] = q.j;
                x[a + 3] = q.k;
            }
            AttitudeCoordinates::Euler321 => {
                let (roll, pitch, yaw) = r.euler_angles();
                x[a] = roll;
                x[a + 1] = pitch;
                x[a + 2] = yaw;
            }
        }
        x.fixed_rows_mut::<3>(self.velocity())
            .copy_from(&r.velocity_body_m_s);
        x.fixed_rows_mut::<3>(self.angular_velocity())
            .copy_from(&r.angular_velocity_body_rad_s);
        let mut write_modes = |start: usize, s: &ModalState| {
            let n = s.q.len();
            x.rows_mut(start, n).copy_from(&s.q);
            x.rows_mut(start + n, n).copy_from(&s.q_dot);
        };
        write_modes(self.body_modes(), &state.body_modes);
        for (i, s) in state.surface_modes.iter().enumerate() {
            write_modes(self.surface_modes(i), s);
        }
        Ok(())
    }

    /// Reads `x` into `state` (buffers of the right sizes, e.g. from
    /// [`VehicleDynamics::zero_state`](super::VehicleDynamics::zero_state)), normalizing a
    /// quaternion attitude. No allocation.
    pub fn unpack(&self, x: &DVector<f64>, state: &mut VehicleState) -> Result<(), DynamicsError> {
        self.check_state(state)?;
        check_len(|| "state vector".into(), self.len(), x.len())?;
        check_finite(|| "state vector".into(), x.iter())?;
        let r = &mut state.rigid;
        r.position_ned_m = x.fixed_rows::<3>(0).into_owned();
        let a = Self::ATTITUDE;
        r.attitude = match self.attitude {
            AttitudeCoordinates::Quaternion => {
                let q = Quaternion::new(x[a], x[a + 1], x[a + 2], x[a + 3]);
                let norm = q.norm();
                if !(norm > 0.0 && norm.is_finite()) {
                    return Err(DynamicsError::DegenerateQuaternion);
                }
                UnitQuaternion::new_unchecked(q / norm)
            }
            AttitudeCoordinates::Euler321 => frames::attitude_from_euler(x[a], x[a + 1], x[a + 2]),
        };
        r.velocity_body_m_s = x.fixed_rows::<3>(self.velocity()).into_owned();
        r.angular_velocity_body_rad_s = x.fixed_rows::<3>(self.angular_velocity()).into_owned();
        let read_modes = |start: usize, s: &mut ModalState| {
            let n = s.q.len();
            s.q.copy_from(&x.rows(start, n));
            s.q_dot.copy_from(&x.rows(start + n, n));
        };
        read_modes(self.body_modes(), &mut state.body_modes);
        for (i, s) in state.surface_modes.iter_mut().enumerate() {
            read_modes(self.surface_modes(i), s);
        }
        Ok(())
    }

    /// Writes the derivative of the state `x` into `dx`: the quaternion rate, or the 3-2-1
    /// Euler rates from the body rates at the Euler angles in `x` (an error at gimbal lock).
    /// No allocation.
    pub fn pack_derivative(
        &self,
        x: &DVector<f64>,
        derivative: &VehicleDerivative,
        dx: &mut DVector<f64>,
    ) -> Result<(), DynamicsError> {
        check_len(|| "state vector".into(), self.len(), x.len())?;
        check_len(|| "state derivative vector".into(), self.len(), dx.len())?;
        check_len(
            || "surface modal rates".into(),
            self.n_surface_modes.len(),
            derivative.surface_modes.len(),
        )?;
        let d = &derivative.rigid;
        dx.fixed_rows_mut::<3>(0)
            .copy_from(&d.position_rate_ned_m_s);
        let a = Self::ATTITUDE;
        match self.attitude {
            AttitudeCoordinates::Quaternion => {
                let q = &d.attitude_rate;
                dx[a] = q.w;
                dx[a + 1] = q.i;
                dx[a + 2] = q.j;
                dx[a + 3] = q.k;
            }
            AttitudeCoordinates::Euler321 => {
                let rates = x.fixed_rows::<3>(self.angular_velocity()).into_owned();
                let euler = frames::euler_rates(x[a], x[a + 1], &rates).ok_or(
                    DynamicsError::GimbalLock {
                        pitch_deg: x[a + 1].to_degrees(),
                    },
                )?;
                dx.fixed_rows_mut::<3>(a).copy_from(&euler);
            }
        }
        dx.fixed_rows_mut::<3>(self.velocity())
            .copy_from(&d.acceleration_body_m_s2);
        dx.fixed_rows_mut::<3>(self.angular_velocity())
            .copy_from(&d.angular_acceleration_body_rad_s2);
        let mut write_rates = |what: &str, start: usize, n: usize, m: &ModalRate| {
            check_len(|| format!("{what} modal rates"), n, m.q_ddot.len())?;
            check_len(|| format!("{what} modal rates"), n, m.q_dot.len())?;
            dx.rows_mut(start, n).copy_from(&m.q_dot);
            dx.rows_mut(start + n, n).copy_from(&m.q_ddot);
            Ok::<(), DynamicsError>(())
        };
        write_rates(
            "body",
            self.body_modes(),
            self.n_body_modes,
            &derivative.body_modes,
        )?;
        for (i, (&n, m)) in self
            .n_surface_modes
            .iter()
            .zip(&derivative.surface_modes)
            .enumerate()
        {
            write_rates("surface", self.surface_modes(i), n, m)?;
        }
        Ok(())
    }

    /// Rescales a quaternion attitude in `x` to unit norm (after an integration step; the
    /// Runge-Kutta update does not keep the norm). No-op for Euler angles.
    pub fn normalize_attitude(&self, x: &mut DVector<f64>) -> Result<(), DynamicsError> {
        if self.attitude == AttitudeCoordinates::Euler321 {
            return Ok(());
        }
        let a = Self::ATTITUDE;
        let norm = x.rows(a, 4).norm();
        if !(norm > 0.0 && norm.is_finite()) {
            return Err(DynamicsError::DegenerateQuaternion);
        }
        x.rows_mut(a, 4).unscale_mut(norm);
        Ok(())
    }
}
