//! The surfaces that follow the body: the monolithic model's lifting surfaces (rotated by the
//! elevon) and the fixed vertical fin of either model. Each is OML moved by the body's beam modes
//! whose aero and friction loads go straight to the body and to its generalized forces; they are
//! evaluated with the body and published with it on `main_body/loads`.

use super::*;

impl PartitionedVehicle {
    /// The surfaces that follow the body (the monolithic model's lifting surfaces, rotated by the
    /// elevon, and the fixed vertical fin): OML following the body's modes whose aero loads go
    /// straight to the body and to its generalized forces.
    pub(super) fn evaluate_followers(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        flight: &FlightCondition,
    ) -> Result<(), VehicleError> {
        let cg = self.mass.center_of_mass_m;
        let p_inf = flight.freestream.pressure_pa;
        let elevon = controls.elevon;
        let surface = |r: RegionKind| r == RegionKind::LiftingSurface;
        for f in &mut self.followers {
            let err = model_error(&f.name);
            f.shapes
                .deform(&f.base, &state.body_modes.q, &mut f.deformed);
            f.shapes
                .panel_velocities(&f.base, &state.body_modes.q_dot, &mut f.velocities);
            if let Some((planform, side)) = &f.elevon {
                let deflection = elevon.deflection_rad(*side);
                deflect_lifting_surface(&f.deformed, planform, *side, deflection, &mut f.deflected)
                    .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
                let rotation =
                    rotation_about_axis(&pivot_axis(), elevon_rotation_angle_rad(deflection))
                        .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
                for v in &mut f.velocities {
                    *v = rotation * *v;
                }
            }
            // The fixed fin flies its deformed OML as it is (`FollowerSurface::flown_mesh`).
            let mesh = if f.elevon.is_some() {
                &f.deflected
            } else {
                &f.deformed
            };
            let motion = PanelMotion {
                elastic_velocity_m_s: Some(&f.velocities),
            };
            f.aero
                .evaluate(mesh, flight, &motion, &mut f.solution)
                .map_err(&err)?;
            let mut loads = integrate_pressure(mesh, &f.solution.pressure_pa, p_inf, &cg, surface);
            if let Some(friction) = &mut f.friction {
                loads = loads
                    + friction
                        .loads(mesh, flight, &f.solution, &motion, &cg, surface)
                        .map_err(&err)?;
            }
            generalized_forces(
                mesh,
                &f.shapes,
                &f.solution.pressure_pa,
                p_inf,
                surface,
                &mut f.generalized,
            )
            .map_err(|e| err(ModelError::inconsistent("coupling", e.to_string())))?;
            f.loads = loads;
        }
        Ok(())
    }
}
