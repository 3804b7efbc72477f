//! Loads on the plate: nodal loads to generalized forces and resultants, and the root loads by
//! force summation through the torque-tube element (the body's side of the interface).

use super::*;

/// Converts a 12-row element block of generalized forces at held root dofs into the load on
/// the tube (force, moment about `pivot`): w rows give −f ẑ at the node, βx rows −f about y,
/// βy rows +f about x (βy = −θx).
pub(super) fn root_load_rows(
    plate: &PlateModel,
    e: usize,
    forces: &DMatrix<f64>,
    pivot: &Point3<f64>,
) -> DMatrix<f64> {
    let mut out = DMatrix::<f64>::zeros(6, forces.ncols());
    let nodes = plate.grid.elements[e];
    for (k, &n) in nodes.iter().enumerate() {
        let held = plate.supports.bending[n];
        let r = plate.grid.positions_m[n] - pivot;
        for c in 0..forces.ncols() {
            if held[0] {
                let f = Vector3::new(0.0, 0.0, -forces[(3 * k, c)]);
                let m = r.cross(&f);
                out[(2, c)] += f.z;
                out[(3, c)] += m.x;
                out[(4, c)] += m.y;
                out[(5, c)] += m.z;
            }
            if held[1] {
                out[(4, c)] -= forces[(3 * k + 1, c)];
            }
            if held[2] {
                out[(3, c)] += forces[(3 * k + 2, c)];
            }
        }
    }
    out
}

/// The tube's six rigid motions on element `e`'s bending dofs (12 × 6, columns x, y, z
/// translation and rotation about x, y, z through the pivot): w = 1 for z; roll w = y − y_p,
/// βy = −1; pitch w = −(x − x_p), βx = 1; the in-plane motions (x, y, yaw) move no bending dof.
/// Rᵀ g is then the force and moment about the pivot of nodal bending forces g (virtual work).
pub(super) fn tube_rigid_motions(plate: &PlateModel, e: usize) -> DMatrix<f64> {
    let pivot = plate.grid.pivot_m;
    let mut r = DMatrix::<f64>::zeros(12, 6);
    for (k, &n) in plate.grid.elements[e].iter().enumerate() {
        let p = plate.grid.positions_m[n];
        r[(3 * k, 2)] = 1.0;
        r[(3 * k, 3)] = p.y - pivot.y;
        r[(3 * k + 2, 3)] = -1.0;
        r[(3 * k, 4)] = -(p.x - pivot.x);
        r[(3 * k + 1, 4)] = 1.0;
    }
    r
}

/// The mirror image in y of a load about a point: a polar force flips y, an axial moment flips
/// x and z.
pub(super) fn mirror_in_y(mut loads: Loads) -> Loads {
    loads.force_n.y = -loads.force_n.y;
    loads.moment_nm.x = -loads.moment_nm.x;
    loads.moment_nm.z = -loads.moment_nm.z;
    loads
}

/// Checks that each modal vector has `r` entries, naming the one that does not.
pub(super) fn check_modal_lengths(
    r: usize,
    vectors: [(&str, &DVector<f64>); 3],
) -> Result<(), ModelError> {
    for (what, v) in vectors {
        if v.len() != r {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{} {what} given, the model has {r} Ritz coordinates",
                    v.len()
                ),
            ));
        }
    }
    Ok(())
}

/// A root load with a non-finite component is an error, not NaN.
pub(super) fn finite_root_load(loads: Loads) -> Result<Loads, ModelError> {
    if loads
        .force_n
        .iter()
        .chain(loads.moment_nm.iter())
        .any(|v| !v.is_finite())
    {
        return Err(ModelError::NonFinite {
            model: NAME.to_owned(),
            quantity: "root load".to_owned(),
            location: String::new(),
        });
    }
    Ok(loads)
}

impl RootLoads for RitzPlate {
    fn root_reference_m(&self) -> Point3<f64> {
        RitzPlate::root_reference_m(self)
    }

    fn root_loads(
        &self,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        modal_accelerations: &DVector<f64>,
        applied: &Loads,
    ) -> Result<Loads, ModelError> {
        self.root_loads_by_force_summation(
            modal_coordinates,
            modal_velocities,
            modal_accelerations,
            applied,
        )
    }
}

impl MassDistribution for RitzPlate {
    /// Node masses ([`PlateModel::node_masses_kg`]: ρ ∫ N_i m dA + m_ns ∫ N_i dA) at the
    /// mid-plane nodes (exact mass and first moment for the bilinear thickness of a solid
    /// section; inertia of the lumped masses, omitting each section's own rotary inertia),
    /// mirrored for the left surface.
    fn mass_properties(&self) -> MassProperties {
        let grid = &self.plate.grid;
        let mirror = if self.side == grid.side { 1.0 } else { -1.0 };
        let at = |p: &Point3<f64>| Point3::new(p.x, mirror * p.y, p.z);
        let node_masses = self.plate.node_masses_kg();
        let masses = node_masses.iter().copied();
        let mass_kg: f64 = masses.clone().sum();
        let first: Vector3<f64> = masses
            .clone()
            .zip(&grid.positions_m)
            .map(|(m, p)| at(p).coords * m)
            .sum();
        let center = Point3::from(first / mass_kg);
        let mut inertia = Matrix3::zeros();
        for (m, p) in masses.zip(&grid.positions_m) {
            let d = at(p) - center;
            inertia += m * (Matrix3::identity() * d.norm_squared() - d * d.transpose());
        }
        MassProperties {
            mass_kg,
            center_of_mass_m: center,
            inertia_kg_m2: inertia,
        }
    }
}

impl RigidBodyCoupling for RitzPlate {
    fn rigid_dofs(&self) -> &[RigidDof] {
        &[
            RigidDof::TranslationX,
            RigidDof::TranslationZ,
            RigidDof::RotationX,
            RigidDof::RotationY,
        ]
    }

    fn rigid_reference_point_m(&self) -> Point3<f64> {
        let p = self.plate.grid.pivot_m;
        let mirror = if self.side == self.plate.grid.side {
            1.0
        } else {
            -1.0
        };
        Point3::new(p.x, mirror * p.y, p.z)
    }

    fn rigid_coupling(&self) -> &DMatrix<f64> {
        &self.rigid_coupling
    }
}

impl RitzPlate {
    /// Checks nodal bending loads: one (F_z N, moment conjugate to βx N m, to βy N m) per grid
    /// node, all finite.
    pub(super) fn check_nodal_loads(&self, nodal_loads: &[[f64; 3]]) -> Result<(), ModelError> {
        let n = self.plate.grid.n_nodes();
        if nodal_loads.len() != n {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{} nodal loads given, the structural grid has {n} nodes",
                    nodal_loads.len()
                ),
            ));
        }
        if let Some(i) = nodal_loads
            .iter()
            .position(|f| f.iter().any(|v| !v.is_finite()))
        {
            return Err(ModelError::NonFinite {
                model: NAME.to_owned(),
                quantity: "nodal load".to_owned(),
                location: format!(" at structural node {i}"),
            });
        }
        Ok(())
    }

    /// Generalized forces Q = Φᵀ f of nodal bending loads on the structural grid (this grid's
    /// side; per node F_z along body z in N, then the moments conjugate to βx and βy in N m;
    /// loads on held dofs go straight to the support and do not enter).
    pub fn generalized_forces(&self, nodal_loads: &[[f64; 3]]) -> Result<DVector<f64>, ModelError> {
        self.check_nodal_loads(nodal_loads)?;
        let f = self.plate.to_equations(|n| nodal_loads[n]);
        Ok(self.basis.tr_mul(&DVector::from_vec(f)))
    }

    /// Resultant about [`RitzPlate::root_reference_m`] of nodal bending loads on the structural
    /// grid (as [`RitzPlate::generalized_forces`]), every node included: F_z = Σ F, M_x =
    /// Σ (y − y_p) F − m_βy, M_y = Σ −(x − x_p) F + m_βx; the applied load for
    /// [`RitzPlate::root_loads_by_force_summation`] when the loads are nodal.
    pub fn nodal_load_resultant(&self, nodal_loads: &[[f64; 3]]) -> Result<Loads, ModelError> {
        self.check_nodal_loads(nodal_loads)?;
        let g = &self.plate.grid;
        let mut l = Loads::default();
        for (p, f) in g.positions_m.iter().zip(nodal_loads) {
            l.force_n.z += f[0];
            l.moment_nm.x += (p.y - g.pivot_m.y) * f[0] - f[2];
            l.moment_nm.y += -(p.x - g.pivot_m.x) * f[0] + f[1];
        }
        finite_root_load(self.on_model_side(l))
    }

    /// The load the surface exerts on the tube by force summation (module docs): the applied
    /// load minus the inertia of the elastic motion, L = F_applied − Rᵀ M Φ q̈, force (N) and
    /// moment about [`RitzPlate::root_reference_m`] (N m), body axes of the selected side.
    /// `applied` is the resultant of every external load on the surface about that point (the
    /// root row's included: e.g. `integrate_pressure` over the surface's panels, or
    /// [`RitzPlate::nodal_load_resultant`]). Velocities enter no term (damping is internal)
    /// but are checked like the rest. The tube's own rigid acceleration is the coordinator's
    /// ([`RitzPlate::rigid_body_mass`], [`RitzPlate::rigid_body_coupling`]).
    pub fn root_loads_by_force_summation(
        &self,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        modal_accelerations: &DVector<f64>,
        applied: &Loads,
    ) -> Result<Loads, ModelError> {
        check_modal_lengths(
            self.basis.ncols(),
            [
                ("modal coordinates", modal_coordinates),
                ("modal velocities", modal_velocities),
                ("modal accelerations", modal_accelerations),
            ],
        )?;
        let mut inertia = Loads::default();
        for c in 0..self.basis.ncols() {
            let a = modal_accelerations[c];
            for k in 0..3 {
                inertia.force_n[k] += self.root_inertia[(k, c)] * a;
                inertia.moment_nm[k] += self.root_inertia[(k + 3, c)] * a;
            }
        }
        let inertia = self.on_model_side(inertia);
        finite_root_load(Loads {
            force_n: applied.force_n - inertia.force_n,
            moment_nm: applied.moment_nm - inertia.moment_nm,
        })
    }

    /// A load computed on the grid's side, as seen on the selected side.
    pub(super) fn on_model_side(&self, loads: Loads) -> Loads {
        if self.side == self.plate.grid.side {
            loads
        } else {
            mirror_in_y(loads)
        }
    }
}
