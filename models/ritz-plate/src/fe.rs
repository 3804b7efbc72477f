//! Element matrices of the flat four-node plate: MITC4 Mindlin-Reissner bending (Bathe & Dvorkin,
//! "A four-node plate bending element based on Mindlin/Reissner plate theory and a mixed
//! interpolation", Int. J. Numer. Meth. Eng. 21 (1985) 367-383), bilinear (Q4) membrane,
//! consistent mass, and the membrane-prestress geometric stiffness of the transverse
//! displacement (Cook, Malkus, Plesha & Witt, Concepts and Applications of FEA, 4th ed., ch. 18, stress
//! stiffness).
//!
//! Kinematics: u(z) = u₀ + z βx, v(z) = v₀ + z βy, w, with z measured from the mid-plane along
//! body z (down). Bending dofs per node (w, βx, βy); membrane dofs (u, v). Curvatures
//! κ = (βx,x, βy,y, βx,y + βy,x), transverse shear γ = (w,x + βx, w,y + βy). Thickness varies
//! bilinearly over the element (nodal values); all integrals use 2 × 2 Gauss points.

use nalgebra::{Matrix2, SMatrix, SVector, Vector2};

/// Shear correction factor κ = 5/6 (Reissner).
pub const SHEAR_CORRECTION: f64 = 5.0 / 6.0;

/// 12 × 12 bending-block matrix (w, βx, βy per node).
pub type Mat12 = SMatrix<f64, 12, 12>;
/// 8 × 8 membrane-block matrix (u, v per node).
pub type Mat8 = SMatrix<f64, 8, 8>;
/// 4 × 4 matrix on the transverse displacements w.
pub type Mat4 = SMatrix<f64, 4, 4>;

/// Geometry of one flat quadrilateral: corner (x, y), counter-clockwise, and corner thickness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quad {
    pub xy: [[f64; 2]; 4],
    pub thickness_m: [f64; 4],
}

/// Natural coordinates of the corners.
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];

/// 2 × 2 Gauss points (weights 1).
fn gauss_points() -> [(f64, f64); 4] {
    let g = 1.0 / 3f64.sqrt();
    [(-g, -g), (g, -g), (g, g), (-g, g)]
}

/// Bilinear shape functions and their natural derivatives at (s, t).
fn shape(s: f64, t: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let mut n = [0.0; 4];
    let mut ds = [0.0; 4];
    let mut dt = [0.0; 4];
    for (k, &(sk, tk)) in CORNERS.iter().enumerate() {
        n[k] = 0.25 * (1.0 + sk * s) * (1.0 + tk * t);
        ds[k] = 0.25 * sk * (1.0 + tk * t);
        dt[k] = 0.25 * tk * (1.0 + sk * s);
    }
    (n, ds, dt)
}

/// Everything an integrand needs at one point.
struct Point {
    n: [f64; 4],
    dx: [f64; 4],
    dy: [f64; 4],
    /// J = [[x,s, y,s], [x,t, y,t]].
    jac: Matrix2<f64>,
    det: f64,
    thickness: f64,
}

impl Quad {
    fn point(&self, s: f64, t: f64) -> Point {
        let (n, ds, dt) = shape(s, t);
        let mut jac = Matrix2::<f64>::zeros();
        for k in 0..4 {
            jac[(0, 0)] += ds[k] * self.xy[k][0];
            jac[(0, 1)] += ds[k] * self.xy[k][1];
            jac[(1, 0)] += dt[k] * self.xy[k][0];
            jac[(1, 1)] += dt[k] * self.xy[k][1];
        }
        let det = jac.determinant();
        let inv = Matrix2::new(jac[(1, 1)], -jac[(0, 1)], -jac[(1, 0)], jac[(0, 0)]) / det;
        let mut dx = [0.0; 4];
        let mut dy = [0.0; 4];
        for k in 0..4 {
            let d = inv * Vector2::new(ds[k], dt[k]);
            dx[k] = d[0];
            dy[k] = d[1];
        }
        let thickness = (0..4).map(|k| n[k] * self.thickness_m[k]).sum();
        Point {
            n,
            dx,
            dy,
            jac,
            det,
            thickness,
        }
    }

    /// Element area, m².
    pub fn area_m2(&self) -> f64 {
        gauss_points()
            .iter()
            .map(|&(s, t)| self.point(s, t).det.abs())
            .sum()
    }
}

/// Plane-stress constitutive pattern [[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]] / (1 − ν²).
fn plane_stress(nu: f64) -> SMatrix<f64, 3, 3> {
    SMatrix::<f64, 3, 3>::new(1.0, nu, 0.0, nu, 1.0, 0.0, 0.0, 0.0, 0.5 * (1.0 - nu))
        / (1.0 - nu * nu)
}

/// Covariant transverse shear strain rows (γ_s, γ_t) at natural point (s, t) from the
/// displacement interpolation (12 bending dofs).
fn covariant_shear(quad: &Quad, s: f64, t: f64) -> (SVector<f64, 12>, SVector<f64, 12>) {
    let p = quad.point(s, t);
    let (_, ds, dt) = shape(s, t);
    let mut gs = SVector::<f64, 12>::zeros();
    let mut gt = SVector::<f64, 12>::zeros();
    for k in 0..4 {
        gs[3 * k] = ds[k];
        gs[3 * k + 1] = p.n[k] * p.jac[(0, 0)];
        gs[3 * k + 2] = p.n[k] * p.jac[(0, 1)];
        gt[3 * k] = dt[k];
        gt[3 * k + 1] = p.n[k] * p.jac[(1, 0)];
        gt[3 * k + 2] = p.n[k] * p.jac[(1, 1)];
    }
    (gs, gt)
}

/// MITC4 bending + shear stiffness for modulus `e_pa` and Poisson's ratio `nu`:
/// K = ∫ B_bᵀ D_b B_b + B_sᵀ D_s B_s dA, D_b = E t³/12 C(ν), D_s = κ G t I, with the shear
/// strains interpolated from the edge-midpoint tying points (Bathe & Dvorkin 1985).
pub fn bending_stiffness(quad: &Quad, e_pa: f64, nu: f64) -> Mat12 {
    let c = plane_stress(nu) * e_pa;
    let g = e_pa / (2.0 * (1.0 + nu));
    // Tying points A (−1, 0), B (0, −1), C (1, 0), D (0, 1).
    let (gs_b, _) = covariant_shear(quad, 0.0, -1.0);
    let (gs_d, _) = covariant_shear(quad, 0.0, 1.0);
    let (_, gt_a) = covariant_shear(quad, -1.0, 0.0);
    let (_, gt_c) = covariant_shear(quad, 1.0, 0.0);
    let mut k = Mat12::zeros();
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let w = p.det.abs();
        let mut bb = SMatrix::<f64, 3, 12>::zeros();
        for n in 0..4 {
            bb[(0, 3 * n + 1)] = p.dx[n];
            bb[(1, 3 * n + 2)] = p.dy[n];
            bb[(2, 3 * n + 1)] = p.dy[n];
            bb[(2, 3 * n + 2)] = p.dx[n];
        }
        let db = c * (p.thickness.powi(3) / 12.0);
        k += bb.transpose() * db * bb * w;
        let gs = gs_b * (0.5 * (1.0 - t)) + gs_d * (0.5 * (1.0 + t));
        let gt = gt_a * (0.5 * (1.0 - s)) + gt_c * (0.5 * (1.0 + s));
        let inv = p.jac.try_inverse().unwrap_or_else(Matrix2::zeros);
        let mut bs = SMatrix::<f64, 2, 12>::zeros();
        for col in 0..12 {
            let cart = inv * Vector2::new(gs[col], gt[col]);
            bs[(0, col)] = cart[0];
            bs[(1, col)] = cart[1];
        }
        k += bs.transpose() * bs * (SHEAR_CORRECTION * g * p.thickness * w);
    }
    k
}

/// Consistent bending-block mass: ρ ∫ t N_i N_j (w) + t³/12 N_i N_j (βx, βy) dA.
pub fn bending_mass(quad: &Quad, density_kg_m3: f64) -> Mat12 {
    let mut m = Mat12::zeros();
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let w = p.det.abs() * density_kg_m3;
        let rotary = p.thickness.powi(3) / 12.0;
        for i in 0..4 {
            for j in 0..4 {
                let nn = p.n[i] * p.n[j] * w;
                m[(3 * i, 3 * j)] += p.thickness * nn;
                m[(3 * i + 1, 3 * j + 1)] += rotary * nn;
                m[(3 * i + 2, 3 * j + 2)] += rotary * nn;
            }
        }
    }
    m
}

/// Consistent mass of a non-structural mass per unit area m (TPS layers, equipment) carried by
/// the nodes: m ∫ N_i N_j dA on w, u and v (rows 0, 3, 6, 9 of the bending block here; the
/// membrane block takes [`area_mass_membrane`]); no rotary inertia (the layers' own
/// m (h/2 + t/2)² is left out, as thin-plate theory leaves out rotary inertia).
pub fn area_mass_bending(quad: &Quad, mass_kg_m2: f64) -> Mat12 {
    let mut m = Mat12::zeros();
    for (i, j, nn) in area_mass_products(quad, mass_kg_m2) {
        m[(3 * i, 3 * j)] += nn;
    }
    m
}

/// [`area_mass_bending`] on the membrane block (u, v).
pub fn area_mass_membrane(quad: &Quad, mass_kg_m2: f64) -> Mat8 {
    let mut m = Mat8::zeros();
    for (i, j, nn) in area_mass_products(quad, mass_kg_m2) {
        m[(2 * i, 2 * j)] += nn;
        m[(2 * i + 1, 2 * j + 1)] += nn;
    }
    m
}

/// (i, j, m N_i N_j |J|) at every Gauss point: the terms of m ∫ N_i N_j dA.
fn area_mass_products(quad: &Quad, mass_kg_m2: f64) -> Vec<(usize, usize, f64)> {
    gauss_points()
        .into_iter()
        .flat_map(|(s, t)| {
            let p = quad.point(s, t);
            let w = p.det.abs() * mass_kg_m2;
            (0..4).flat_map(move |i| (0..4).map(move |j| (i, j, p.n[i] * p.n[j] * w)))
        })
        .collect()
}

/// Membrane strain-displacement matrix B_m (3 × 8) at a point.
fn membrane_b(p: &Point) -> SMatrix<f64, 3, 8> {
    let mut b = SMatrix::<f64, 3, 8>::zeros();
    for n in 0..4 {
        b[(0, 2 * n)] = p.dx[n];
        b[(1, 2 * n + 1)] = p.dy[n];
        b[(2, 2 * n)] = p.dy[n];
        b[(2, 2 * n + 1)] = p.dx[n];
    }
    b
}

/// Q4 membrane stiffness ∫ B_mᵀ (E t C(ν)) B_m dA.
pub fn membrane_stiffness(quad: &Quad, e_pa: f64, nu: f64) -> Mat8 {
    let c = plane_stress(nu) * e_pa;
    let mut k = Mat8::zeros();
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let b = membrane_b(&p);
        k += b.transpose() * c * b * (p.thickness * p.det.abs());
    }
    k
}

/// Consistent membrane mass ρ ∫ t N_i N_j dA on u and on v.
pub fn membrane_mass(quad: &Quad, density_kg_m3: f64) -> Mat8 {
    let mut m = Mat8::zeros();
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let w = p.det.abs() * density_kg_m3 * p.thickness;
        for i in 0..4 {
            for j in 0..4 {
                let nn = p.n[i] * p.n[j] * w;
                m[(2 * i, 2 * j)] += nn;
                m[(2 * i + 1, 2 * j + 1)] += nn;
            }
        }
    }
    m
}

/// The membrane quantities of a unit isotropic free strain ε_th = 1 at modulus `e_pa`:
/// `load` = ∫ B_mᵀ A (1, 1, 0) dA (equivalent nodal forces), `stress` = ∫ A B_m dA and
/// `free` = ∫ A (1, 1, 0) dA, with A = E t C(ν); the element-mean stress resultants are then
/// N̄ = (stress u − ε_th free) / area.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MembraneThermal {
    pub load: SVector<f64, 8>,
    pub stress: SMatrix<f64, 3, 8>,
    pub free: SVector<f64, 3>,
    pub area_m2: f64,
}

/// [`MembraneThermal`] of `quad`.
pub fn membrane_thermal(quad: &Quad, e_pa: f64, nu: f64) -> MembraneThermal {
    let c = plane_stress(nu) * e_pa;
    let unit = SVector::<f64, 3>::new(1.0, 1.0, 0.0);
    let mut out = MembraneThermal {
        load: SVector::zeros(),
        stress: SMatrix::zeros(),
        free: SVector::zeros(),
        area_m2: 0.0,
    };
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let w = p.det.abs();
        let a = c * p.thickness;
        let b = membrane_b(&p);
        out.load += b.transpose() * a * unit * w;
        out.stress += a * b * w;
        out.free += a * unit * w;
        out.area_m2 += w;
    }
    out
}

/// Equivalent nodal bending load of a unit through-thickness free-strain difference
/// Δε = ε_th(z = +t/2) − ε_th(z = −t/2) = 1 (lower face minus upper face, z down), ε_th linear in z:
/// free curvature κ_T = Δε/t (1, 1, 0), thermal moment M_T = ∫ E ε_th z dz = E t² Δε / 12,
/// f = ∫ B_bᵀ D_b κ_T dA = ∫ B_bᵀ (M_T / (1 − ν)) (1, 1, 0) dA (Boley & Weiner, Theory of Thermal
/// Stresses, 1960, ch. 12, thin plates).
pub fn bending_thermal(quad: &Quad, e_pa: f64, nu: f64) -> SVector<f64, 12> {
    let unit = SVector::<f64, 3>::new(1.0, 1.0, 0.0);
    let c = plane_stress(nu) * e_pa;
    let mut f = SVector::<f64, 12>::zeros();
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let mut bb = SMatrix::<f64, 3, 12>::zeros();
        for n in 0..4 {
            bb[(0, 3 * n + 1)] = p.dx[n];
            bb[(1, 3 * n + 2)] = p.dy[n];
            bb[(2, 3 * n + 1)] = p.dy[n];
            bb[(2, 3 * n + 2)] = p.dx[n];
        }
        // D_b κ_T = (E t³/12) C (Δε/t): the t² keeps sharp edges (t = 0) finite.
        f += bb.transpose() * c * unit * (p.thickness.powi(2) / 12.0 * p.det.abs());
    }
    f
}

/// Geometric stiffness patterns on w for unit resultants: G_xx = ∫ w,xᵀ w,x, G_yy = ∫ w,yᵀ w,y,
/// G_xy = ∫ (w,xᵀ w,y + w,yᵀ w,x) dA, so K_G = N_xx G_xx + N_yy G_yy + N_xy G_xy.
pub fn geometric_patterns(quad: &Quad) -> [Mat4; 3] {
    let mut g = [Mat4::zeros(); 3];
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let w = p.det.abs();
        for i in 0..4 {
            for j in 0..4 {
                g[0][(i, j)] += p.dx[i] * p.dx[j] * w;
                g[1][(i, j)] += p.dy[i] * p.dy[j] * w;
                g[2][(i, j)] += (p.dx[i] * p.dy[j] + p.dy[i] * p.dx[j]) * w;
            }
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    fn skewed() -> Quad {
        Quad {
            xy: [[0.0, 0.0], [1.2, 0.1], [1.0, 0.9], [-0.2, 1.1]],
            thickness_m: [0.05, 0.04, 0.03, 0.06],
        }
    }

    /// Rigid-body motions (w = 1; pitch w = −x, βx = 1; roll w = y, βy = −1) store no strain
    /// energy; the MITC4 element passes this on distorted geometry.
    #[test]
    fn rigid_body_motions_are_stress_free() {
        let q = skewed();
        let k = bending_stiffness(&q, 1e11, 0.3);
        let mut modes = [SVector::<f64, 12>::zeros(); 3];
        for n in 0..4 {
            let [x, y] = q.xy[n];
            modes[0][3 * n] = 1.0;
            modes[1][3 * n] = -x;
            modes[1][3 * n + 1] = 1.0;
            modes[2][3 * n] = y;
            modes[2][3 * n + 2] = -1.0;
        }
        let scale = k.norm();
        for m in modes {
            assert!((k * m).norm() < 1e-10 * scale, "{}", (k * m).norm());
        }
        let km = membrane_stiffness(&q, 1e11, 0.3);
        let mut rigid = [SVector::<f64, 8>::zeros(); 3];
        for n in 0..4 {
            let [x, y] = q.xy[n];
            rigid[0][2 * n] = 1.0;
            rigid[1][2 * n + 1] = 1.0;
            rigid[2][2 * n] = -y;
            rigid[2][2 * n + 1] = x;
        }
        for m in rigid {
            assert!((km * m).norm() < 1e-10 * km.norm());
        }
        // Mass: total transverse mass ρ V; symmetric positive.
        let mass = bending_mass(&q, 1000.0);
        let ones = modes[0];
        let total = (ones.transpose() * mass * ones)[(0, 0)];
        let volume: f64 = gauss_points()
            .iter()
            .map(|&(s, t)| {
                let p = q.point(s, t);
                p.det * p.thickness
            })
            .sum();
        assert!((total / (1000.0 * volume) - 1.0).abs() < 1e-12);
        // A free isotropic expansion u = ε x, v = ε y makes the element stress-free.
        let th = membrane_thermal(&q, 1e11, 0.3);
        let mut u = SVector::<f64, 8>::zeros();
        for n in 0..4 {
            u[2 * n] = q.xy[n][0];
            u[2 * n + 1] = q.xy[n][1];
        }
        let n_bar = (th.stress * u - th.free) / th.area_m2;
        assert!(n_bar.norm() < 1e-6 * th.free.norm() / th.area_m2);
        assert!((km * u - th.load).norm() < 1e-9 * th.load.norm());
    }

    /// The thermal-moment load is self-equilibrated (rigid motions do no work on it), and the
    /// free curvature κ_T = 1/t of a uniform-thickness element (βx = κ x, βy = κ y, w = −κ (x² +
    /// y²)/2 at the nodes) makes it the element's elastic force K u: no stress, as for the free
    /// plate under a linear through-thickness temperature (Boley & Weiner 1960).
    #[test]
    fn thermal_moment_load_is_self_equilibrated_and_matches_the_free_curvature() {
        let mut q = skewed();
        let f = bending_thermal(&q, 1e11, 0.3);
        // Virtual work of f on w = 1; pitch (w = −x, βx = 1); roll (w = y, βy = −1).
        let mut work = [0.0; 3];
        for n in 0..4 {
            let [x, y] = q.xy[n];
            work[0] += f[3 * n];
            work[1] += -x * f[3 * n] + f[3 * n + 1];
            work[2] += y * f[3 * n] - f[3 * n + 2];
        }
        for w in work {
            assert!(w.abs() < 1e-10 * f.norm(), "{work:?}");
        }
        q.thickness_m = [0.04; 4];
        let f = bending_thermal(&q, 1e11, 0.3);
        let k = bending_stiffness(&q, 1e11, 0.3);
        let kappa = 1.0 / 0.04;
        let mut u = SVector::<f64, 12>::zeros();
        for n in 0..4 {
            let [x, y] = q.xy[n];
            u[3 * n] = -0.5 * kappa * (x * x + y * y);
            u[3 * n + 1] = kappa * x;
            u[3 * n + 2] = kappa * y;
        }
        assert!(
            (k * u - f).norm() < 1e-9 * f.norm(),
            "{}",
            (k * u - f).norm()
        );
    }
}
