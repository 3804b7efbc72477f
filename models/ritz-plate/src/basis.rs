//! The Ritz basis: free-vibration modes of the full-order plate augmented with static load
//! shapes, Rayleigh-Ritz on them, and each vector's classification (bending, torsion, ...).

use super::*;

/// Names free-vibration mode shapes by their dominant content along the span: mean deflection
/// (bending), linear chordwise slope (torsion) or the remainder (chordwise bending), numbered
/// by order of appearance of each kind.
pub(super) fn classify_modes(plate: &PlateModel, modes: &DMatrix<f64>) -> Vec<String> {
    let g = &plate.grid;
    let (nc, ns) = (g.nodes_chordwise(), g.nodes_spanwise());
    let mut counts = [0usize; 3];
    let kinds = ["bending", "torsion", "chordwise bending"];
    (0..modes.ncols())
        .map(|c| {
            let v: Vec<f64> = modes.column(c).iter().copied().collect();
            let mut energy = [0.0; 3];
            for j in 0..ns {
                let pts: Vec<(f64, f64)> = (0..nc)
                    .map(|i| {
                        let n = g.node_index(i, j);
                        (g.positions_m[n].x, plate.nodal_value(&v, n)[0])
                    })
                    .collect();
                let k = pts.len() as f64;
                let mx = pts.iter().map(|p| p.0).sum::<f64>() / k;
                let mw = pts.iter().map(|p| p.1).sum::<f64>() / k;
                let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
                let sxw: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - mw)).sum();
                let slope = if sxx > 0.0 { sxw / sxx } else { 0.0 };
                energy[0] += k * mw * mw;
                energy[1] += slope * slope * sxx;
                energy[2] += pts
                    .iter()
                    .map(|p| (p.1 - mw - slope * (p.0 - mx)).powi(2))
                    .sum::<f64>();
            }
            let kind = (0..3)
                .max_by(|&a, &b| energy[a].total_cmp(&energy[b]))
                .unwrap_or(0);
            counts[kind] += 1;
            format!("{} {}", kinds[kind], counts[kind])
        })
        .collect()
}

impl RitzPlate {
    /// Builds the full-order plate on `grid` (root nodes clamped), its Ritz basis at 293 K and
    /// the reduced element contributions.
    pub fn new(
        grid: SurfaceGrid,
        material: Material,
        settings: &Settings,
    ) -> Result<Self, ModelError> {
        let supports = Supports::free(grid.n_nodes()).clamp(&grid.root_nodes);
        Self::with_supports(grid, material, supports, settings)
    }

    /// [`RitzPlate::new`] with any supports (plate-theory checks: simply supported edges,
    /// statically determinate in-plane supports for free thermal expansion, ...). Root loads
    /// are then the reactions at every held bending dof.
    pub fn with_supports(
        grid: SurfaceGrid,
        material: Material,
        supports: Supports,
        settings: &Settings,
    ) -> Result<Self, ModelError> {
        let n_modes = settings.free_vibration_modes;
        if !(1..=50).contains(&n_modes) {
            return Err(ModelError::out_of_range(
                NAME,
                "free_vibration_modes",
                n_modes as f64,
                "1 to 50",
            ));
        }
        if settings.static_shapes > STATIC_SHAPES.len() {
            return Err(ModelError::out_of_range(
                NAME,
                "static_shapes",
                settings.static_shapes as f64,
                "0 to 5",
            ));
        }
        let zeta = settings.damping_ratio;
        if !(zeta.is_finite() && (0.0..1.0).contains(&zeta)) {
            return Err(ModelError::out_of_range(
                NAME,
                "damping_ratio",
                zeta,
                "[0, 1)",
            ));
        }
        let added = settings.non_structural_mass_kg_m2;
        if !(added.is_finite() && added >= 0.0) {
            return Err(ModelError::out_of_range(
                NAME,
                "non_structural_mass_kg_m2",
                added,
                "finite and >= 0 kg/m²",
            ));
        }
        let section = match &settings.built_up {
            None => fe::Section::Solid,
            Some(b) => b.section().map_err(|(key, v)| {
                ModelError::out_of_range(NAME, &format!("built_up.{key}"), v, "finite and > 0 m")
            })?,
        };
        let plate = PlateModel::with_section(grid, material, supports, section)
            .map_err(model_error)?
            .with_non_structural_mass(added);
        let requested =
            n_modes + settings.static_shapes + usize::from(settings.thermal_moment_shape);
        if requested > plate.bending_map.n_equations / 4 {
            return Err(model_error(PlateError::TooFewDofs {
                requested,
                available: plate.bending_map.n_equations,
            }));
        }
        let (_, modes) = plate.modes(None, n_modes).map_err(model_error)?;
        let mut names = classify_modes(&plate, &modes);
        let (basis, eigenvalues, static_names) = Self::augment(
            &plate,
            modes,
            settings.static_shapes,
            settings.thermal_moment_shape,
        )?;
        names.extend(static_names);
        let mut model = Self::from_basis(plate, basis, eigenvalues, names, zeta);
        model.reset_reference()?;
        Ok(model)
    }

    /// Adds the static load shapes (and, with `thermal_shape`, the uniform thermal-moment
    /// shape): K⁻¹ f, M-orthogonalized (twice, modified Gram-Schmidt) against the modes and
    /// each other, then rotated so the static block of K_r is diagonal.
    pub(super) fn augment(
        plate: &PlateModel,
        modes: DMatrix<f64>,
        n_static: usize,
        thermal_shape: bool,
    ) -> Result<AugmentedBasis, ModelError> {
        if n_static == 0 && !thermal_shape {
            let (b, eigenvalues) = Self::rayleigh_ritz(plate, modes)?;
            return Ok((b, eigenvalues, Vec::new()));
        }
        let g = &plate.grid;
        let (nc, ns) = (g.nodes_chordwise(), g.nodes_spanwise());
        let tip = g.edge_nodes(GridEdge::Tip);
        let tip_mid_x = 0.5 * (g.positions_m[tip[0]].x + g.positions_m[tip[nc - 1]].x);
        let mut loads: Vec<Vec<f64>> = (0..n_static)
            .map(|k| {
                plate.to_equations(|n| {
                    let (i, j) = (n % nc, n / nc);
                    let a = g.node_areas_m2[n];
                    let u = g.chord_fractions[i];
                    let eta = g.span_fractions[j];
                    let w = match k {
                        0 => a,
                        1 => f64::from(u8::from(j == ns - 1)),
                        2 => {
                            if j == ns - 1 {
                                g.positions_m[n].x - tip_mid_x
                            } else {
                                0.0
                            }
                        }
                        3 => a * (u - 0.5),
                        _ => a * eta,
                    };
                    [w, 0.0, 0.0]
                })
            })
            .collect();
        if thermal_shape {
            let uniform = ElementState {
                thermal_strain_difference: 1e-3,
                ..ElementState::REFERENCE
            };
            loads.push(plate.thermal_moment_load(&vec![uniform; plate.n_elements()]));
        }
        let f = DMatrix::from_fn(plate.bending_map.n_equations, loads.len(), |r, c| {
            loads[c][r]
        });
        let shapes = plate.static_solve(&f).map_err(model_error)?;
        let m = plate.assemble_mass();
        let m_times = |v: &[f64]| {
            let mut out = vec![0.0; v.len()];
            m.mul_vec(v, &mut out);
            out
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut basis: Vec<Vec<f64>> = modes
            .column_iter()
            .map(|c| c.iter().copied().collect())
            .collect();
        let n_modes = basis.len();
        for col in shapes.column_iter() {
            let mut v: Vec<f64> = col.iter().copied().collect();
            let norm0 = dot(&v, &m_times(&v)).sqrt();
            for _ in 0..2 {
                for b in &basis {
                    let c = dot(b, &m_times(&v));
                    v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
                }
            }
            let norm = dot(&v, &m_times(&v)).sqrt();
            // A shape already (numerically) in the span adds nothing; skip it.
            if norm.is_nan() || norm <= 1e-8 * norm0 {
                continue;
            }
            v.iter_mut().for_each(|x| *x /= norm);
            basis.push(v);
        }
        let n_eq = plate.bending_map.n_equations;
        let b = DMatrix::from_fn(n_eq, basis.len(), |r, c| basis[c][r]);
        let n_s = basis.len() - n_modes;
        // A final Rayleigh-Ritz on the whole basis makes it exactly M-orthonormal and
        // K-orthogonal (the modes from subspace iteration carry ~1e-6 vector errors); the
        // first n_modes Ritz values are the modes' own eigenvalues.
        let (b, eigenvalues) = Self::rayleigh_ritz(plate, b)?;
        let names = (0..n_s)
            .map(|i| format!("static-shape Ritz vector {}", i + 1))
            .collect();
        Ok((b, eigenvalues, names))
    }

    /// Rotates `basis` to the eigenvectors of (Bᵀ K B, Bᵀ M B) at 293 K: M-orthonormal,
    /// K-diagonal, ascending Ritz values.
    pub(super) fn rayleigh_ritz(
        plate: &PlateModel,
        basis: DMatrix<f64>,
    ) -> Result<(DMatrix<f64>, Vec<f64>), ModelError> {
        let (k, m) = (plate.assemble_stiffness(None), plate.assemble_mass());
        let n = basis.nrows();
        let mut kb = DMatrix::<f64>::zeros(n, basis.ncols());
        let mut mb = DMatrix::<f64>::zeros(n, basis.ncols());
        let mut out = vec![0.0; n];
        for (c, col) in basis.column_iter().enumerate() {
            let v: Vec<f64> = col.iter().copied().collect();
            k.mul_vec(&v, &mut out);
            kb.column_mut(c).copy_from_slice(&out);
            m.mul_vec(&v, &mut out);
            mb.column_mut(c).copy_from_slice(&out);
        }
        let ritz = generalized_symmetric_eigen(
            &(basis.transpose() * kb),
            &(basis.transpose() * mb),
            basis.ncols(),
        )
        .map_err(|_| ModelError::inconsistent(NAME, "the Ritz basis is linearly dependent"))?;
        Ok((basis * ritz.vectors, ritz.values))
    }

    /// Precomputes the reduced element matrices, root-load and rigid-body couplings.
    pub(super) fn from_basis(
        plate: PlateModel,
        basis: DMatrix<f64>,
        eigenvalues: Vec<f64>,
        names: Vec<String>,
        damping_ratio: f64,
    ) -> Self {
        let r = basis.ncols();
        let n_e = plate.n_elements();
        let mut stiffness = vec![0.0; n_e * r * r];
        let mut geometric = vec![0.0; 3 * n_e * r * r];
        let mut root_elements = Vec::new();
        let mut root_mass = DMatrix::<f64>::zeros(6, r);
        let pivot = plate.grid.pivot_m;
        let mut rigid_coupling = DMatrix::<f64>::zeros(r, 4);
        let mut rigid_mass = Matrix3::<f64>::zeros();
        let mut thermal = vec![0.0; n_e * r];
        let mut root_inertia = DMatrix::<f64>::zeros(6, r);
        for e in 0..n_e {
            let be = plate.element_rows(&basis, e);
            let ke = DMatrix::from_fn(12, 12, |a, b| plate.bending_stiffness[e][(a, b)]);
            let kr = be.transpose() * &ke * &be;
            stiffness[e * r * r..(e + 1) * r * r].copy_from_slice(kr.as_slice());
            let mut ge = [
                DMatrix::<f64>::zeros(12, 12),
                DMatrix::zeros(12, 12),
                DMatrix::zeros(12, 12),
            ];
            for (c, g) in ge.iter_mut().enumerate() {
                for i in 0..4 {
                    for j in 0..4 {
                        g[(3 * i, 3 * j)] = plate.geometric[e][c][(i, j)];
                    }
                }
                let gr = be.transpose() * &*g * &be;
                let start = (3 * e + c) * r * r;
                geometric[start..start + r * r].copy_from_slice(gr.as_slice());
            }
            let me = DMatrix::from_fn(12, 12, |a, b| plate.bending_mass[e][(a, b)]);
            let nodes = plate.grid.elements[e];
            if nodes
                .iter()
                .any(|&n| plate.supports.bending[n].iter().any(|&h| h))
            {
                let stiff = root_load_rows(&plate, e, &(&ke * &be), &pivot);
                let geo = [0, 1, 2].map(|c| root_load_rows(&plate, e, &(&ge[c] * &be), &pivot));
                root_mass += root_load_rows(&plate, e, &(&me * &be), &pivot);
                root_elements.push(RootElement {
                    element: e,
                    stiffness: stiff,
                    geometric: geo,
                });
            }
            // Rigid motions of the tube on the element's nodes: z translation (w = 1) and pitch
            // about the pivot axis (w = −(x − x_p), βx = 1); x translation is in-plane.
            let mut rz = DMatrix::<f64>::zeros(12, 3);
            for (k, &n) in nodes.iter().enumerate() {
                let x = plate.grid.positions_m[n].x;
                rz[(3 * k, 1)] = 1.0;
                rz[(3 * k, 2)] = -(x - pivot.x);
                rz[(3 * k + 1, 2)] = 1.0;
            }
            // The coupling's columns: x, z, roll and pitch of the tube (the order of
            // `rigid_dofs`); roll is column 3 of the six tube motions.
            let tube = tube_rigid_motions(&plate, e);
            let mut coupling = DMatrix::<f64>::zeros(12, 4);
            coupling.column_mut(0).copy_from(&rz.column(0));
            coupling.column_mut(1).copy_from(&rz.column(1));
            coupling.column_mut(2).copy_from(&tube.column(3));
            coupling.column_mut(3).copy_from(&rz.column(2));
            rigid_coupling += be.transpose() * &me * &coupling;
            root_inertia += tube.transpose() * &me * &be;
            let fe = DVector::from_column_slice(plate.bending_thermal[e].as_slice());
            thermal[e * r..(e + 1) * r].copy_from_slice((be.transpose() * fe).as_slice());
            let mrr = rz.transpose() * &me * &rz;
            for a in 1..3 {
                for b in 1..3 {
                    rigid_mass[(a, b)] += mrr[(a, b)];
                }
            }
            let mm = &plate.membrane_mass[e];
            // Σ_ij M_m[u_i, u_j]: the element's mass in x translation.
            rigid_mass[(0, 0)] += (0..4)
                .flat_map(|i| (0..4).map(move |j| (i, j)))
                .map(|(i, j)| mm[(2 * i, 2 * j)])
                .sum::<f64>();
        }
        let n_eq_m = plate.membrane_map.n_equations;
        let modal = ModalModel {
            names,
            mass: DMatrix::identity(r, r),
            damping: DMatrix::zeros(r, r),
            stiffness: DMatrix::from_diagonal(&DVector::from_vec(eigenvalues.clone())),
        };
        Self {
            membrane_k: plate.membrane_matrix(),
            membrane_rhs: vec![0.0; n_eq_m],
            states: vec![ElementState::REFERENCE; n_e],
            resultants: vec![[0.0; 3]; n_e],
            side: plate.grid.side,
            plate,
            damping_ratio,
            basis,
            reference_eigenvalues: eigenvalues.clone(),
            reduced: Reduced {
                size: r,
                stiffness,
                geometric,
                thermal,
            },
            root_elements,
            root_mass,
            root_stiffness: DMatrix::zeros(6, r),
            root_inertia,
            thermal_forces: DVector::zeros(r),
            rigid_coupling,
            rigid_mass,
            modal,
            eigenvalues,
            eigenvectors: DMatrix::identity(r, r),
            symmetric_eigen: SymmetricEigenSolver::new(r),
        }
    }

    /// The reference (293 K, stress-free) state: K_r from the reduced element sums.
    pub(super) fn reset_reference(&mut self) -> Result<(), ModelError> {
        for s in &mut self.states {
            *s = ElementState::REFERENCE;
        }
        self.resultants.iter_mut().for_each(|r| *r = [0.0; 3]);
        self.update_reduced()
    }
}
