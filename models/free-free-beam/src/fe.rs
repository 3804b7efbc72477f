//! Finite elements of the beam: mesh along the body axis, element matrices, assembly, rigid-body
//! vectors and interpolation of a nodal vector to any station.
//!
//! Six DOFs per node in body axes: u (x), v (y), w (z) of the beam axis, and the section
//! rotations θx, θy, θz. Stations are measured by s = −x, the distance aft of the nose. Bending
//! uses Hermite cubics in s: vertical (x-z plane) with w' = dw/ds = θy (a nose-down rotation about
//! +y, since x̂ → x̂ − θy ẑ), lateral (x-y plane) with v' = dv/ds = −θz (x̂ → x̂ + θz ŷ). Axial and
//! torsion use linear elements. All mass matrices are consistent (same shape functions).
//! Reference: Przemieniecki, Theory of Matrix Structural Analysis (1968), ch. 5 and 11.

use nalgebra::{DMatrix, DVector, Matrix2, Matrix4, Vector3};

/// DOFs per node: u, v, w, θx, θy, θz.
pub const DOF_PER_NODE: usize = 6;

/// What a DOF belongs to, and so which family of modes it carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ModeKind {
    /// Bending in the x-y plane (v, θz), stiffness EI_zz.
    LateralBending,
    /// Bending in the x-z plane (w, θy), stiffness EI_yy.
    VerticalBending,
    /// Twist about the beam axis (θx), stiffness GJ.
    Torsion,
    /// Stretching along x (u), stiffness EA.
    Axial,
}

impl ModeKind {
    /// All kinds, in the order of [`ModeKind::index`].
    pub const ALL: [ModeKind; 4] = [
        ModeKind::LateralBending,
        ModeKind::VerticalBending,
        ModeKind::Torsion,
        ModeKind::Axial,
    ];

    /// Position in [`ModeKind::ALL`].
    pub fn index(self) -> usize {
        match self {
            ModeKind::LateralBending => 0,
            ModeKind::VerticalBending => 1,
            ModeKind::Torsion => 2,
            ModeKind::Axial => 3,
        }
    }

    /// "lateral bending", "vertical bending", "torsion", "axial".
    pub fn label(self) -> &'static str {
        match self {
            ModeKind::LateralBending => "lateral bending",
            ModeKind::VerticalBending => "vertical bending",
            ModeKind::Torsion => "torsion",
            ModeKind::Axial => "axial",
        }
    }

    /// The kind carried by local DOF `k` (0..6) of a node.
    pub fn of_local_dof(k: usize) -> ModeKind {
        match k {
            0 => ModeKind::Axial,
            1 | 5 => ModeKind::LateralBending,
            2 | 4 => ModeKind::VerticalBending,
            _ => ModeKind::Torsion,
        }
    }
}

/// Section properties of one element (constant along it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// μ, kg/m.
    pub mass_per_length_kg_m: f64,
    /// Rotary inertia about the beam axis per unit length, I_x, kg m²/m.
    pub torsional_inertia_kg_m: f64,
    /// EI_zz (x-y plane), N m².
    pub lateral_bending_stiffness_n_m2: f64,
    /// EI_yy (x-z plane), N m².
    pub vertical_bending_stiffness_n_m2: f64,
    /// GJ, N m².
    pub torsional_stiffness_n_m2: f64,
    /// EA, N.
    pub axial_stiffness_n: f64,
}

/// A beam discretized into elements along s = −x (nose at s = 0).
#[derive(Debug, Clone, PartialEq)]
pub struct BeamMesh {
    /// Node stations, m, strictly increasing from 0 to the beam length.
    pub nodes_s_m: Vec<f64>,
    /// Section of each element (nodes i, i+1).
    pub sections: Vec<Section>,
}

/// Displacement and small rotation of a cross-section, body axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionMotion {
    /// Axis displacement (u, v, w), m per unit modal coordinate.
    pub displacement: Vector3<f64>,
    /// Rotation (θx, θy, θz), rad per unit modal coordinate.
    pub rotation: Vector3<f64>,
}

/// Hermite cubic bending stiffness for (d1, d1', d2, d2'), ' = d/ds: EI/h³ [12 6h −12 6h; ...].
fn hermite_stiffness(ei: f64, h: f64) -> Matrix4<f64> {
    let c = ei / h.powi(3);
    let h2 = h * h;
    Matrix4::new(
        12.0,
        6.0 * h,
        -12.0,
        6.0 * h,
        6.0 * h,
        4.0 * h2,
        -6.0 * h,
        2.0 * h2,
        -12.0,
        -6.0 * h,
        12.0,
        -6.0 * h,
        6.0 * h,
        2.0 * h2,
        -6.0 * h,
        4.0 * h2,
    ) * c
}

/// Consistent Hermite cubic mass: μh/420 [156 22h 54 −13h; ...] (Przemieniecki eq. 11.41).
fn hermite_mass(mu: f64, h: f64) -> Matrix4<f64> {
    let c = mu * h / 420.0;
    let h2 = h * h;
    Matrix4::new(
        156.0,
        22.0 * h,
        54.0,
        -13.0 * h,
        22.0 * h,
        4.0 * h2,
        13.0 * h,
        -3.0 * h2,
        54.0,
        13.0 * h,
        156.0,
        -22.0 * h,
        -13.0 * h,
        -3.0 * h2,
        -22.0 * h,
        4.0 * h2,
    ) * c
}

/// Linear element stiffness k/h [1 −1; −1 1] (axial EA, torsion GJ).
fn linear_stiffness(k: f64, h: f64) -> Matrix2<f64> {
    Matrix2::new(1.0, -1.0, -1.0, 1.0) * (k / h)
}

/// Consistent linear element mass m h/6 [2 1; 1 2] (axial μ, torsion I_x).
fn linear_mass(m: f64, h: f64) -> Matrix2<f64> {
    Matrix2::new(2.0, 1.0, 1.0, 2.0) * (m * h / 6.0)
}

/// Hermite shape functions and their s-derivatives at ξ = (s − s_a)/h ∈ [0, 1].
fn hermite_shape(xi: f64, h: f64) -> ([f64; 4], [f64; 4]) {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    (
        [
            1.0 - 3.0 * x2 + 2.0 * x3,
            h * (xi - 2.0 * x2 + x3),
            3.0 * x2 - 2.0 * x3,
            h * (-x2 + x3),
        ],
        [
            (-6.0 * xi + 6.0 * x2) / h,
            1.0 - 4.0 * xi + 3.0 * x2,
            (6.0 * xi - 6.0 * x2) / h,
            -2.0 * xi + 3.0 * x2,
        ],
    )
}

impl BeamMesh {
    /// Elements of a beam made of `segments` (length m, section) laid nose to tail, each split
    /// into the given number of equal elements.
    pub fn from_segments(segments: &[(f64, Section, usize)]) -> Self {
        let mut nodes_s_m = vec![0.0];
        let mut sections = Vec::new();
        let mut start = 0.0;
        for &(length, section, count) in segments {
            for i in 1..=count {
                // Exact segment ends, so a junction node sits exactly where the section changes.
                nodes_s_m.push(if i == count {
                    start + length
                } else {
                    start + length * i as f64 / count as f64
                });
                sections.push(section);
            }
            start += length;
        }
        Self {
            nodes_s_m,
            sections,
        }
    }

    pub fn n_nodes(&self) -> usize {
        self.nodes_s_m.len()
    }

    pub fn n_dof(&self) -> usize {
        DOF_PER_NODE * self.n_nodes()
    }

    /// Beam length, m.
    pub fn length_m(&self) -> f64 {
        self.nodes_s_m.last().copied().unwrap_or(0.0)
    }

    /// The kind carried by each global DOF.
    pub fn dof_kinds(&self) -> Vec<ModeKind> {
        (0..self.n_dof())
            .map(|i| ModeKind::of_local_dof(i % DOF_PER_NODE))
            .collect()
    }

    /// Global mass and stiffness matrices, assembled from the element matrices.
    pub fn assemble(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.n_dof();
        let mut mass = DMatrix::zeros(n, n);
        let mut stiffness = DMatrix::zeros(n, n);
        for (e, sec) in self.sections.iter().enumerate() {
            let h = self.nodes_s_m[e + 1] - self.nodes_s_m[e];
            let (a, b) = (DOF_PER_NODE * e, DOF_PER_NODE * (e + 1));
            // Linear fields: axial u (local 0) and torsion θx (local 3).
            for (local, k_e, m_e) in [
                (
                    0,
                    linear_stiffness(sec.axial_stiffness_n, h),
                    linear_mass(sec.mass_per_length_kg_m, h),
                ),
                (
                    3,
                    linear_stiffness(sec.torsional_stiffness_n_m2, h),
                    linear_mass(sec.torsional_inertia_kg_m, h),
                ),
            ] {
                let dofs = [a + local, b + local];
                for i in 0..2 {
                    for j in 0..2 {
                        stiffness[(dofs[i], dofs[j])] += k_e[(i, j)];
                        mass[(dofs[i], dofs[j])] += m_e[(i, j)];
                    }
                }
            }
            // Bending: (w, θy) with θy = +w', (v, θz) with θz = −v'; the sign flips the
            // rotation rows and columns of the standard (d, d') element.
            for (translation, rotation, ei, sign) in [
                (2, 4, sec.vertical_bending_stiffness_n_m2, 1.0),
                (1, 5, sec.lateral_bending_stiffness_n_m2, -1.0),
            ] {
                let k_e = hermite_stiffness(ei, h);
                let m_e = hermite_mass(sec.mass_per_length_kg_m, h);
                let dofs = [a + translation, a + rotation, b + translation, b + rotation];
                let signs = [1.0, sign, 1.0, sign];
                for i in 0..4 {
                    for j in 0..4 {
                        let t = signs[i] * signs[j];
                        stiffness[(dofs[i], dofs[j])] += t * k_e[(i, j)];
                        mass[(dofs[i], dofs[j])] += t * m_e[(i, j)];
                    }
                }
            }
        }
        (mass, stiffness)
    }

    /// The six rigid-body motions as nodal vectors (columns): translations along x, y, z and
    /// small rotations about x, y, z through the nose station of the beam axis.
    ///
    /// Rotation α about axis â moves a point r by α â × r: about y, w = −α x = α s, θy = α; about
    /// z, v = α x = −α s, θz = α.
    pub fn rigid_body_modes(&self) -> DMatrix<f64> {
        let n = self.n_dof();
        let mut r = DMatrix::zeros(n, 6);
        for (i, &s) in self.nodes_s_m.iter().enumerate() {
            let d = DOF_PER_NODE * i;
            r[(d, 0)] = 1.0;
            r[(d + 1, 1)] = 1.0;
            r[(d + 2, 2)] = 1.0;
            r[(d + 3, 3)] = 1.0;
            r[(d + 2, 4)] = s;
            r[(d + 4, 4)] = 1.0;
            r[(d + 1, 5)] = -s;
            r[(d + 5, 5)] = 1.0;
        }
        r
    }

    /// Element index and local coordinate ξ ∈ [0, 1] of station `s_m` (clamped to the beam).
    pub fn locate(&self, s_m: f64) -> (usize, f64, f64) {
        let n_el = self.sections.len();
        let s = s_m.clamp(0.0, self.length_m());
        // First node strictly beyond s, minus one; the last element takes the tail itself.
        let e = self
            .nodes_s_m
            .partition_point(|&node| node <= s)
            .saturating_sub(1)
            .min(n_el.saturating_sub(1));
        let h = self.nodes_s_m[e + 1] - self.nodes_s_m[e];
        (e, ((s - self.nodes_s_m[e]) / h).clamp(0.0, 1.0), h)
    }

    /// Cross-section motion at station `s_m` (clamped to the beam) of the nodal vector `phi`,
    /// interpolated with the element shape functions.
    pub fn section_motion(&self, phi: &DVector<f64>, s_m: f64) -> SectionMotion {
        self.section_motion_of(|i| phi[i], s_m)
    }

    /// [`BeamMesh::section_motion`] for a nodal vector given by its entries.
    pub fn section_motion_of(&self, phi: impl Fn(usize) -> f64, s_m: f64) -> SectionMotion {
        let (e, xi, h) = self.locate(s_m);
        let (a, b) = (DOF_PER_NODE * e, DOF_PER_NODE * (e + 1));
        let linear = |k: usize| (1.0 - xi) * phi(a + k) + xi * phi(b + k);
        let (n, dn) = hermite_shape(xi, h);
        // Nodal (d, d') of each plane: vertical (w, θy), lateral (v, −θz).
        let vertical = [phi(a + 2), phi(a + 4), phi(b + 2), phi(b + 4)];
        let lateral = [phi(a + 1), -phi(a + 5), phi(b + 1), -phi(b + 5)];
        let dot = |f: &[f64; 4], d: &[f64; 4]| f.iter().zip(d).map(|(x, y)| x * y).sum::<f64>();
        SectionMotion {
            displacement: Vector3::new(linear(0), dot(&n, &lateral), dot(&n, &vertical)),
            rotation: Vector3::new(linear(3), dot(&dn, &vertical), -dot(&dn, &lateral)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn section() -> Section {
        Section {
            mass_per_length_kg_m: 2.0,
            torsional_inertia_kg_m: 0.5,
            lateral_bending_stiffness_n_m2: 7.0,
            vertical_bending_stiffness_n_m2: 3.0,
            torsional_stiffness_n_m2: 5.0,
            axial_stiffness_n: 11.0,
        }
    }

    #[test]
    fn element_mass_sums_to_the_segment_mass_and_rigid_motions_are_stress_free() {
        let mesh = BeamMesh::from_segments(&[(1.5, section(), 3), (2.5, section(), 2)]);
        let (m, k) = mesh.assemble();
        let r = mesh.rigid_body_modes();
        // K R = 0: rigid motions strain nothing.
        assert!((&k * &r).amax() < 1e-12 * k.amax());
        // Translation kinetic energy = total mass, rotation about x = total I_x L.
        let rtmr = r.transpose() * &m * &r;
        for i in 0..3 {
            assert_relative_eq!(rtmr[(i, i)], 2.0 * 4.0, max_relative = 1e-12);
        }
        assert_relative_eq!(rtmr[(3, 3)], 0.5 * 4.0, max_relative = 1e-12);
        // Rotation about y through the nose: ∫ μ s² ds = μ L³/3.
        assert_relative_eq!(rtmr[(4, 4)], 2.0 * 64.0 / 3.0, max_relative = 1e-12);
        assert_relative_eq!(rtmr[(5, 5)], 2.0 * 64.0 / 3.0, max_relative = 1e-12);
    }

    #[test]
    fn interpolation_reproduces_nodes_and_rigid_rotations() {
        let mesh = BeamMesh::from_segments(&[(4.0, section(), 4)]);
        let r = mesh.rigid_body_modes();
        // Rotation about y: w = s, θy = 1 everywhere, exactly (cubic shape functions).
        for s in [0.0, 0.3, 1.0, 2.7, 4.0, 5.0] {
            let m = mesh.section_motion(&r.column(4).into_owned(), s);
            let sc = s.min(4.0);
            assert_relative_eq!(m.displacement.z, sc, epsilon = 1e-12);
            assert_relative_eq!(m.rotation.y, 1.0, epsilon = 1e-12);
            let m = mesh.section_motion(&r.column(5).into_owned(), s);
            assert_relative_eq!(m.displacement.y, -sc, epsilon = 1e-12);
            assert_relative_eq!(m.rotation.z, 1.0, epsilon = 1e-12);
        }
    }
}
