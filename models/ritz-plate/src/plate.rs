//! The full-order plate model on a [`SurfaceGrid`]: element matrices, supports, the thermal
//! membrane solve, assembly of K(T) + K_G(σ(T)) and M, free-vibration modes and static
//! deflections. The Ritz model ([`crate::RitzPlate`]) is built from it once (one file: one model
//! type, [`PlateModel`], with the DOF numbering and supports its assemblies are built on).
//!
//! Every element takes the mean temperature T_e of its four nodes: modulus E(T_e), free strain
//! ε_e = α_sec(T_e) (T_e − 293 K). Element stiffnesses scale with s_e = E(T_e)/E(293 K)
//! (Poisson's ratio is constant), so reference element matrices are computed once. A
//! through-thickness temperature difference ΔT (lower face minus upper, linear in z) adds the
//! face free-strain difference Δε_e = ε_th(T_e + ΔT_e/2) − ε_th(T_e − ΔT_e/2), whose thermal
//! moment loads the bending block ([`fe::bending_thermal`]).

use hsv_core::linalg::{BandedMatrix, EigenError, NotPositiveDefinite, lowest_banded_eigenpairs};
use hsv_core::material::{Material, MaterialError, SECANT_REFERENCE_TEMPERATURE_K};
use hsv_core::surface_grid::{GridEdge, SurfaceGrid};
use nalgebra::{DMatrix, SVector};

use crate::fe::{self, Mat4, Mat8, Mat12, MembraneThermal, Quad, Section};

/// Bending dofs per node: w, βx, βy.
pub const BENDING_DOFS: usize = 3;
/// Membrane dofs per node: u, v.
pub const MEMBRANE_DOFS: usize = 2;

/// Which nodal dofs are held (true = fixed).
#[derive(Debug, Clone, PartialEq)]
pub struct Supports {
    /// Per node: (u, v) held.
    pub membrane: Vec<[bool; MEMBRANE_DOFS]>,
    /// Per node: (w, βx, βy) held.
    pub bending: Vec<[bool; BENDING_DOFS]>,
}

impl Supports {
    /// Nothing held.
    pub fn free(n_nodes: usize) -> Self {
        Self {
            membrane: vec![[false; 2]; n_nodes],
            bending: vec![[false; 3]; n_nodes],
        }
    }

    /// Clamps `nodes`: every dof held (the torque-tube root or a clamped edge).
    pub fn clamp(mut self, nodes: &[usize]) -> Self {
        for &n in nodes {
            self.membrane[n] = [true; 2];
            self.bending[n] = [true; 3];
        }
        self
    }

    /// Hard simple support on `edge`: w and the rotation about the edge's normal in-plane axis
    /// held (βx on edges along x, βy on edges along y), i.e. the Kirchhoff condition w = ∂w/∂s = 0.
    pub fn simply_support(mut self, grid: &SurfaceGrid, edge: GridEdge) -> Self {
        let nodes = grid.edge_nodes(edge);
        if nodes.len() < 2 {
            return self;
        }
        let (a, b) = (
            grid.positions_m[nodes[0]],
            grid.positions_m[nodes[nodes.len() - 1]],
        );
        let along_x = (b.x - a.x).abs() >= (b.y - a.y).abs();
        for n in nodes {
            self.bending[n][0] = true;
            if along_x {
                self.bending[n][1] = true;
            } else {
                self.bending[n][2] = true;
            }
        }
        self
    }

    /// Holds u and v at `nodes` (an in-plane immovable edge).
    pub fn restrain_in_plane(mut self, nodes: &[usize]) -> Self {
        for &n in nodes {
            self.membrane[n] = [true; 2];
        }
        self
    }

    /// Holds u at `nodes`.
    pub fn hold_u(mut self, nodes: &[usize]) -> Self {
        for &n in nodes {
            self.membrane[n][0] = true;
        }
        self
    }

    /// Holds v at `nodes`.
    pub fn hold_v(mut self, nodes: &[usize]) -> Self {
        for &n in nodes {
            self.membrane[n][1] = true;
        }
        self
    }
}

/// Equation numbers of nodal dofs (None: held), numbered so the band is narrow.
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    /// `equation[node * dofs + d]`.
    pub equation: Vec<Option<usize>>,
    pub dofs_per_node: usize,
    pub n_equations: usize,
    pub bandwidth: usize,
}

impl DofMap {
    fn new(grid: &SurfaceGrid, held: impl Fn(usize, usize) -> bool, dofs: usize) -> Self {
        let (nc, ns) = (grid.nodes_chordwise(), grid.nodes_spanwise());
        // Number along the shorter grid direction first: half-bandwidth ∝ the shorter side.
        let order: Vec<usize> = if nc <= ns {
            (0..ns)
                .flat_map(|j| (0..nc).map(move |i| grid.node_index(i, j)))
                .collect()
        } else {
            (0..nc)
                .flat_map(|i| (0..ns).map(move |j| grid.node_index(i, j)))
                .collect()
        };
        let mut equation = vec![None; grid.n_nodes() * dofs];
        let mut next = 0;
        for node in order {
            for d in 0..dofs {
                if !held(node, d) {
                    equation[node * dofs + d] = Some(next);
                    next += 1;
                }
            }
        }
        let mut bandwidth = 0;
        for el in &grid.elements {
            let eq = &equation;
            let eqs: Vec<usize> = el
                .iter()
                .flat_map(|&n| (0..dofs).filter_map(move |d| eq[n * dofs + d]))
                .collect();
            if let (Some(lo), Some(hi)) = (eqs.iter().min(), eqs.iter().max()) {
                bandwidth = bandwidth.max(hi - lo);
            }
        }
        Self {
            equation,
            dofs_per_node: dofs,
            n_equations: next,
            bandwidth,
        }
    }

    /// Equations of an element's dofs in element order (node-major).
    pub fn element_equations<const N: usize>(&self, nodes: &[usize; 4]) -> [Option<usize>; N] {
        let mut out = [None; N];
        for (k, &n) in nodes.iter().enumerate() {
            for d in 0..self.dofs_per_node {
                out[k * self.dofs_per_node + d] = self.equation[n * self.dofs_per_node + d];
            }
        }
        out
    }
}

/// Why the full-order model failed.
#[derive(Debug, Clone, PartialEq)]
pub enum PlateError {
    Material(MaterialError),
    /// A node temperature (or through-thickness difference, `what`) that is not finite.
    NonFiniteTemperature {
        what: &'static str,
        node: usize,
        value: f64,
    },
    /// Wrong number of node temperatures (or through-thickness differences, `what`).
    TemperatureCount {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    /// K (or K + K_G) is not positive definite: unsupported mechanism or buckled.
    NotPositiveDefinite {
        what: &'static str,
        equation: usize,
        pivot: f64,
    },
    /// The grid has fewer free dofs than requested modes.
    TooFewDofs {
        requested: usize,
        available: usize,
    },
    Eigen(EigenError),
}

impl std::fmt::Display for PlateError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlateError::Material(e) => write!(f, "{e}"),
            PlateError::NonFiniteTemperature { what, node, value } => {
                write!(
                    f,
                    "{what} {value} K at structural node {node} is not finite"
                )
            }
            PlateError::TemperatureCount {
                what,
                got,
                expected,
            } => write!(
                f,
                "{got} {what} given, the structural grid has {expected} nodes"
            ),
            PlateError::NotPositiveDefinite {
                what,
                equation,
                pivot,
            } => write!(
                f,
                "{what} is not positive definite (pivot {pivot:.3e} at equation {equation}): \
                 the plate is unsupported or buckled"
            ),
            PlateError::TooFewDofs {
                requested,
                available,
            } => write!(
                f,
                "the structural grid has {available} free bending dofs, too coarse for \
                 {requested} modes and shapes; refine the grid"
            ),
            PlateError::Eigen(e) => write!(f, "mode solve: {e}"),
        }
    }
}

impl From<MaterialError> for PlateError {
    fn from(e: MaterialError) -> Self {
        PlateError::Material(e)
    }
}

/// Per-element temperature state: stiffness scale s_e = E(T_e)/E_ref, mid-plane free strain ε_e
/// and the free-strain difference Δε_e between the lower (z = +t/2) and upper faces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementState {
    pub stiffness_scale: f64,
    pub thermal_strain: f64,
    pub thermal_strain_difference: f64,
}

impl ElementState {
    /// 293 K, no through-thickness difference.
    pub const REFERENCE: ElementState = ElementState {
        stiffness_scale: 1.0,
        thermal_strain: 0.0,
        thermal_strain_difference: 0.0,
    };
}

/// The element quads of `grid` (corner positions in the plane and depths) filled by `section`.
fn element_quads(grid: &SurfaceGrid, section: Section) -> Vec<Quad> {
    grid.elements
        .iter()
        .map(|el| Quad {
            xy: el.map(|n| [grid.positions_m[n].x, grid.positions_m[n].y]),
            thickness_m: el.map(|n| grid.thickness_m[n]),
            section,
        })
        .collect()
}

/// The full-order plate (module docs).
#[derive(Debug, Clone)]
pub struct PlateModel {
    pub grid: SurfaceGrid,
    pub material: Material,
    pub supports: Supports,
    pub bending_map: DofMap,
    pub membrane_map: DofMap,
    /// E at 293 K, Pa.
    pub reference_modulus_pa: f64,
    /// Element bending stiffness at E_ref.
    pub bending_stiffness: Vec<Mat12>,
    pub bending_mass: Vec<Mat12>,
    pub membrane_stiffness: Vec<Mat8>,
    pub membrane_mass: Vec<Mat8>,
    pub membrane_thermal: Vec<MembraneThermal>,
    /// Bending load of a unit face free-strain difference at E_ref ([`fe::bending_thermal`]).
    pub bending_thermal: Vec<SVector<f64, 12>>,
    /// Geometric stiffness patterns (xx, yy, xy) on w.
    pub geometric: Vec<[Mat4; 3]>,
    /// Non-structural mass per unit planform area in the mass matrices, kg/m² (TPS layers).
    pub non_structural_mass_kg_m2: f64,
    /// What fills the depth between the faces.
    pub section: Section,
}

impl PlateModel {
    /// Element matrices at the reference temperature (293 K) for `grid`, `material`, `supports`,
    /// solid section.
    pub fn new(
        grid: SurfaceGrid,
        material: Material,
        supports: Supports,
    ) -> Result<Self, PlateError> {
        Self::with_section(grid, material, supports, Section::Solid)
    }

    /// [`PlateModel::new`] with the depth filled by `section`.
    pub fn with_section(
        grid: SurfaceGrid,
        material: Material,
        supports: Supports,
        section: Section,
    ) -> Result<Self, PlateError> {
        material.validate()?;
        let e_ref = material.youngs_modulus_pa(SECANT_REFERENCE_TEMPERATURE_K)?;
        let nu = material.poisson_ratio;
        let rho = material.density_kg_m3;
        let quads = element_quads(&grid, section);
        let bending_map = DofMap::new(&grid, |n, d| supports.bending[n][d], BENDING_DOFS);
        let membrane_map = DofMap::new(&grid, |n, d| supports.membrane[n][d], MEMBRANE_DOFS);
        Ok(Self {
            bending_stiffness: quads
                .iter()
                .map(|q| fe::bending_stiffness(q, e_ref, nu))
                .collect(),
            bending_mass: quads.iter().map(|q| fe::bending_mass(q, rho)).collect(),
            membrane_stiffness: quads
                .iter()
                .map(|q| fe::membrane_stiffness(q, e_ref, nu))
                .collect(),
            membrane_mass: quads.iter().map(|q| fe::membrane_mass(q, rho)).collect(),
            membrane_thermal: quads
                .iter()
                .map(|q| fe::membrane_thermal(q, e_ref, nu))
                .collect(),
            bending_thermal: quads
                .iter()
                .map(|q| fe::bending_thermal(q, e_ref, nu))
                .collect(),
            geometric: quads.iter().map(fe::geometric_patterns).collect(),
            non_structural_mass_kg_m2: 0.0,
            section,
            grid,
            material,
            supports,
            bending_map,
            membrane_map,
            reference_modulus_pa: e_ref,
        })
    }

    /// Adds a uniform non-structural mass per unit area (kg/m², ≥ 0) to the bending and
    /// membrane mass matrices ([`fe::area_mass_bending`]); stiffness is unchanged, so a uniform
    /// plate's frequencies scale by √(ρh / (ρh + m)) (Kirchhoff: ω ∝ √(D / (ρh)), Leissa, NASA
    /// SP-160, 1969, eq. 4.1).
    pub fn with_non_structural_mass(mut self, mass_kg_m2: f64) -> Self {
        if mass_kg_m2 != 0.0 {
            for (e, quad) in element_quads(&self.grid, self.section).iter().enumerate() {
                self.bending_mass[e] += fe::area_mass_bending(quad, mass_kg_m2);
                self.membrane_mass[e] += fe::area_mass_membrane(quad, mass_kg_m2);
            }
        }
        self.non_structural_mass_kg_m2 += mass_kg_m2;
        self
    }

    /// Node masses, kg: ρ ∫ N_i m dA of the section plus the non-structural m_ns ∫ N_i dA (a solid
    /// section takes the grid's node volumes, ρ ∫ N_i t dA).
    pub fn node_masses_kg(&self) -> Vec<f64> {
        let rho = self.material.density_kg_m3;
        let added = self.non_structural_mass_kg_m2;
        let structural: Vec<f64> = match self.section {
            Section::Solid => self.grid.node_volumes_m3.iter().map(|v| rho * v).collect(),
            Section::BuiltUp(_) => {
                let mut m = vec![0.0; self.grid.n_nodes()];
                for (quad, el) in element_quads(&self.grid, self.section)
                    .iter()
                    .zip(&self.grid.elements)
                {
                    for (share, &node) in fe::node_mass_shares(quad).iter().zip(el) {
                        m[node] += rho * share;
                    }
                }
                m
            }
        };
        structural
            .iter()
            .zip(&self.grid.node_areas_m2)
            .map(|(m, a)| m + added * a)
            .collect()
    }

    pub fn n_elements(&self) -> usize {
        self.grid.n_elements()
    }

    /// Checks one value per grid node (`what`: singular and plural names), all finite.
    fn check_node_values(
        &self,
        values: &[f64],
        what: (&'static str, &'static str),
    ) -> Result<(), PlateError> {
        if values.len() != self.grid.n_nodes() {
            return Err(PlateError::TemperatureCount {
                what: what.1,
                got: values.len(),
                expected: self.grid.n_nodes(),
            });
        }
        if let Some((node, &value)) = values.iter().enumerate().find(|(_, t)| !t.is_finite()) {
            return Err(PlateError::NonFiniteTemperature {
                what: what.0,
                node,
                value,
            });
        }
        Ok(())
    }

    /// Element states from mid-plane node temperatures (K) and, optionally, node
    /// through-thickness differences ΔT = T(lower face) − T(upper face) (K, linear in z), into
    /// `out` (one per element). Allocation-free.
    pub fn element_states(
        &self,
        node_temperatures_k: &[f64],
        node_differences_k: Option<&[f64]>,
        out: &mut [ElementState],
    ) -> Result<(), PlateError> {
        self.check_node_values(
            node_temperatures_k,
            ("node temperature", "node temperatures"),
        )?;
        if let Some(d) = node_differences_k {
            self.check_node_values(
                d,
                (
                    "through-thickness temperature difference",
                    "through-thickness temperature differences",
                ),
            )?;
        }
        let mean =
            |values: &[f64], el: &[usize; 4]| 0.25 * el.iter().map(|&n| values[n]).sum::<f64>();
        for (e, el) in self.grid.elements.iter().enumerate() {
            let t = mean(node_temperatures_k, el);
            let p = self.material.at(t)?;
            let dt = node_differences_k.map_or(0.0, |d| mean(d, el));
            let thermal_strain_difference = if dt == 0.0 {
                0.0
            } else {
                self.material.thermal_strain(t + 0.5 * dt)?
                    - self.material.thermal_strain(t - 0.5 * dt)?
            };
            out[e] = ElementState {
                stiffness_scale: p.youngs_modulus_pa / self.reference_modulus_pa,
                thermal_strain: p.thermal_expansion_per_k * (t - SECANT_REFERENCE_TEMPERATURE_K),
                thermal_strain_difference,
            };
        }
        Ok(())
    }

    /// Thermal-moment load over the free bending equations, f_T = Σ_e s_e Δε_e f_e
    /// ([`fe::bending_thermal`]): what a through-thickness temperature difference bends the
    /// plate with.
    pub fn thermal_moment_load(&self, states: &[ElementState]) -> Vec<f64> {
        let mut f = vec![0.0; self.bending_map.n_equations];
        for (e, el) in self.grid.elements.iter().enumerate() {
            let scale = states[e].stiffness_scale * states[e].thermal_strain_difference;
            let eqs: [Option<usize>; 12] = self.bending_map.element_equations(el);
            for (a, eq) in eqs.iter().enumerate() {
                if let Some(i) = eq {
                    f[*i] += scale * self.bending_thermal[e][a];
                }
            }
        }
        f
    }

    /// A banded matrix sized for the membrane problem.
    pub fn membrane_matrix(&self) -> BandedMatrix {
        BandedMatrix::zeros(self.membrane_map.n_equations, self.membrane_map.bandwidth)
    }

    /// Thermal membrane solve: K_m(s) u = Σ s_e ε_e f_e, then element-mean stress resultants
    /// N̄_e = s_e (S_e u_e − ε_e n_e) / A_e (N/m; xx, yy, xy) into `resultants`. `k` and `rhs`
    /// are workspaces ([`Self::membrane_matrix`], n_equations long). Allocation-free.
    pub fn membrane_resultants_into(
        &self,
        states: &[ElementState],
        k: &mut BandedMatrix,
        rhs: &mut [f64],
        resultants: &mut [[f64; 3]],
    ) -> Result<(), PlateError> {
        k.clear();
        rhs.iter_mut().for_each(|v| *v = 0.0);
        let map = &self.membrane_map;
        for (e, el) in self.grid.elements.iter().enumerate() {
            let s = states[e].stiffness_scale;
            let eps = states[e].thermal_strain;
            let eqs: [Option<usize>; 8] = map.element_equations(el);
            let ke = &self.membrane_stiffness[e];
            let fe = &self.membrane_thermal[e].load;
            for a in 0..8 {
                let Some(i) = eqs[a] else { continue };
                rhs[i] += s * eps * fe[a];
                for b in 0..8 {
                    if let Some(j) = eqs[b]
                        && j <= i
                    {
                        k.add(i, j, s * ke[(a, b)]);
                    }
                }
            }
        }
        if map.n_equations > 0 {
            k.factorize()
                .map_err(
                    |NotPositiveDefinite { row, pivot }| PlateError::NotPositiveDefinite {
                        what: "the membrane stiffness",
                        equation: row,
                        pivot,
                    },
                )?;
            k.solve_in_place(rhs);
        }
        for (e, el) in self.grid.elements.iter().enumerate() {
            let eqs: [Option<usize>; 8] = map.element_equations(el);
            let u = SVector::<f64, 8>::from_fn(|a, _| eqs[a].map_or(0.0, |i| rhs[i]));
            let th = &self.membrane_thermal[e];
            let s = states[e].stiffness_scale;
            let n = (th.stress * u - th.free * states[e].thermal_strain) * (s / th.area_m2);
            resultants[e] = [n[0], n[1], n[2]];
        }
        Ok(())
    }

    /// States and membrane resultants for node temperatures (allocating convenience).
    pub fn thermal_state(
        &self,
        node_temperatures_k: &[f64],
    ) -> Result<(Vec<ElementState>, Vec<[f64; 3]>), PlateError> {
        let mut states = vec![ElementState::REFERENCE; self.n_elements()];
        self.element_states(node_temperatures_k, None, &mut states)?;
        let mut k = self.membrane_matrix();
        let mut rhs = vec![0.0; self.membrane_map.n_equations];
        let mut res = vec![[0.0; 3]; self.n_elements()];
        self.membrane_resultants_into(&states, &mut k, &mut rhs, &mut res)?;
        Ok((states, res))
    }

    /// Element effective bending stiffness s_e K_e + Σ N_c G_c (on w).
    pub fn element_effective_stiffness(&self, e: usize, scale: f64, resultant: [f64; 3]) -> Mat12 {
        let mut k = self.bending_stiffness[e] * scale;
        let g = &self.geometric[e];
        for i in 0..4 {
            for j in 0..4 {
                k[(3 * i, 3 * j)] += resultant[0] * g[0][(i, j)]
                    + resultant[1] * g[1][(i, j)]
                    + resultant[2] * g[2][(i, j)];
            }
        }
        k
    }

    fn assemble(&self, element: impl Fn(usize) -> Mat12) -> BandedMatrix {
        let map = &self.bending_map;
        let mut k = BandedMatrix::zeros(map.n_equations, map.bandwidth);
        for (e, el) in self.grid.elements.iter().enumerate() {
            let ke = element(e);
            let eqs: [Option<usize>; 12] = map.element_equations(el);
            for a in 0..12 {
                let Some(i) = eqs[a] else { continue };
                for b in 0..12 {
                    if let Some(j) = eqs[b]
                        && j <= i
                    {
                        k.add(i, j, ke[(a, b)]);
                    }
                }
            }
        }
        k
    }

    /// Bending stiffness K(T) + K_G(σ(T)) for element states and resultants (None: 293 K).
    pub fn assemble_stiffness(
        &self,
        thermal: Option<(&[ElementState], &[[f64; 3]])>,
    ) -> BandedMatrix {
        match thermal {
            None => self.assemble(|e| self.bending_stiffness[e]),
            Some((states, res)) => self.assemble(|e| {
                self.element_effective_stiffness(e, states[e].stiffness_scale, res[e])
            }),
        }
    }

    /// Consistent bending-block mass matrix.
    pub fn assemble_mass(&self) -> BandedMatrix {
        self.assemble(|e| self.bending_mass[e])
    }

    /// The lowest `n` free-vibration eigenpairs (ω² in rad²/s², M-orthonormal vectors over
    /// the free bending equations) at node temperatures (None: 293 K, no thermal stress).
    pub fn modes(
        &self,
        node_temperatures_k: Option<&[f64]>,
        n: usize,
    ) -> Result<(Vec<f64>, DMatrix<f64>), PlateError> {
        let available = self.bending_map.n_equations;
        if n == 0 || n > available / 2 {
            return Err(PlateError::TooFewDofs {
                requested: n,
                available,
            });
        }
        let thermal = match node_temperatures_k {
            Some(t) => Some(self.thermal_state(t)?),
            None => None,
        };
        let mut k =
            self.assemble_stiffness(thermal.as_ref().map(|(s, r)| (s.as_slice(), r.as_slice())));
        k.factorize()
            .map_err(
                |NotPositiveDefinite { row, pivot }| PlateError::NotPositiveDefinite {
                    what: "the bending stiffness K + K_G",
                    equation: row,
                    pivot,
                },
            )?;
        let m = self.assemble_mass();
        lowest_banded_eigenpairs(&k, &m, n, 1e-12)
            .map(|modes| (modes.values, modes.vectors))
            .map_err(PlateError::Eigen)
    }

    /// Natural frequencies, Hz, from [`Self::modes`].
    pub fn frequencies_hz(
        &self,
        node_temperatures_k: Option<&[f64]>,
        n: usize,
    ) -> Result<Vec<f64>, PlateError> {
        let (values, _) = self.modes(node_temperatures_k, n)?;
        Ok(values
            .iter()
            .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect())
    }

    /// Static deflection K⁻¹ f at 293 K for loads given per free bending equation.
    pub fn static_solve(&self, loads: &DMatrix<f64>) -> Result<DMatrix<f64>, PlateError> {
        let mut k = self.assemble_stiffness(None);
        k.factorize()
            .map_err(
                |NotPositiveDefinite { row, pivot }| PlateError::NotPositiveDefinite {
                    what: "the bending stiffness",
                    equation: row,
                    pivot,
                },
            )?;
        let mut out = loads.clone();
        for mut c in out.column_iter_mut() {
            let mut v: Vec<f64> = c.iter().copied().collect();
            k.solve_in_place(&mut v);
            c.copy_from_slice(&v);
        }
        Ok(out)
    }

    /// A vector over free bending equations from per-node (w, βx, βy) values.
    pub fn to_equations(&self, nodal: impl Fn(usize) -> [f64; 3]) -> Vec<f64> {
        let mut v = vec![0.0; self.bending_map.n_equations];
        for node in 0..self.grid.n_nodes() {
            for (d, val) in nodal(node).iter().enumerate() {
                if let Some(i) = self.bending_map.equation[node * 3 + d] {
                    v[i] = *val;
                }
            }
        }
        v
    }

    /// Per-node (w, βx, βy) of an equation vector (held dofs are 0).
    pub fn nodal_value(&self, v: &[f64], node: usize) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (d, o) in out.iter_mut().enumerate() {
            if let Some(i) = self.bending_map.equation[node * 3 + d] {
                *o = v[i];
            }
        }
        out
    }

    /// Element bending-dof values (12) of an equation vector.
    pub fn element_values(&self, v: &[f64], e: usize) -> SVector<f64, 12> {
        let eqs: [Option<usize>; 12] = self.bending_map.element_equations(&self.grid.elements[e]);
        SVector::<f64, 12>::from_fn(|a, _| eqs[a].map_or(0.0, |i| v[i]))
    }

    /// Element bending-dof rows (12 × r) of a basis over free equations (held dofs: 0).
    pub fn element_rows(&self, basis: &DMatrix<f64>, e: usize) -> DMatrix<f64> {
        let eqs: [Option<usize>; 12] = self.bending_map.element_equations(&self.grid.elements[e]);
        DMatrix::from_fn(12, basis.ncols(), |a, c| {
            eqs[a].map_or(0.0, |i| basis[(i, c)])
        })
    }
}
