//! Element matrices of the flat four-node plate: MITC4 Mindlin-Reissner bending (Bathe & Dvorkin,
//! "A four-node plate bending element based on Mindlin/Reissner plate theory and a mixed
//! interpolation", Int. J. Numer. Meth. Eng. 21 (1985) 367-383), bilinear (Q4) membrane,
//! consistent mass, and the membrane-prestress geometric stiffness of the transverse
//! displacement (Cook, Malkus, Plesha & Witt, Concepts and Applications of FEA, 4th ed., ch. 18, stress
//! stiffness).
//!
//! Kinematics: u(z) = u₀ + z βx, v(z) = v₀ + z βy, w, with z measured from the mid-plane along
//! body z (down). Bending dofs per node (w, βx, βy); membrane dofs (u, v). Curvatures
//! κ = (βx,x, βy,y, βx,y + βy,x), transverse shear γ = (w,x + βx, w,y + βy). The depth h varies
//! bilinearly over the element (nodal values); what fills it is the element's [`Section`] (solid,
//! or built up of skins and webs), whose properties per unit width every integrand takes at its
//! point; all integrals use 2 × 2 Gauss points.

use nalgebra::{Matrix2, SMatrix, SVector, Vector2};

/// Shear correction factor κ = 5/6 (Reissner).
pub const SHEAR_CORRECTION: f64 = 5.0 / 6.0;

/// 12 × 12 bending-block matrix (w, βx, βy per node).
pub type Mat12 = SMatrix<f64, 12, 12>;
/// 8 × 8 membrane-block matrix (u, v per node).
pub type Mat8 = SMatrix<f64, 8, 8>;
/// 4 × 4 matrix on the transverse displacements w.
pub type Mat4 = SMatrix<f64, 4, 4>;

/// Geometry of one flat quadrilateral: corner (x, y), counter-clockwise, corner depth (the
/// section's thickness, face to face) and what fills the section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quad {
    pub xy: [[f64; 2]; 4],
    pub thickness_m: [f64; 4],
    pub section: Section,
}

/// What fills the plate's depth.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Section {
    /// Solid material face to face.
    #[default]
    Solid,
    /// Built up: two face skins with spar and rib webs between them (a hollow box section).
    BuiltUp(BuiltUp),
}

/// A built-up section: face skins of thickness `skin_m` whose centroids are h − t_s apart, and
/// webs smeared over the planform as web thickness over pitch (spars run spanwise, ribs
/// chordwise). Where the depth is below two skins (the sharp edges) the section is solid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuiltUp {
    /// Skin thickness t_s, m (each face).
    pub skin_m: f64,
    /// Spar webs: t_w / spar pitch (m of web per m of chord).
    pub spar_web_ratio: f64,
    /// Rib webs: t_w / rib pitch (m of web per m of span).
    pub rib_web_ratio: f64,
}

/// Section properties per unit width at one point, as geometric integrals over the material
/// of the section (multiply by E, G or ρ): the isotropic plate takes them in every direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionProperties {
    /// In-plane area A = ∫ dz, m.
    pub membrane_m: f64,
    /// Bending inertia I = ∫ z² dz, m³ (D = E I C(ν)).
    pub bending_m3: f64,
    /// Transverse shear area before the correction κ, m (shear stiffness κ G times this).
    pub shear_m: f64,
    /// Mass per unit area over ρ, m.
    pub mass_m: f64,
    /// Rotary inertia per unit area over ρ, m³.
    pub rotary_m3: f64,
    /// Thermal moment per unit E and unit free-strain difference Δε, m²: across the faces,
    /// linear in z, for a solid section (h²/12); between the two skins for a built-up one.
    pub thermal_moment_m2: f64,
}

impl Section {
    /// The properties at depth `h_m`.
    pub fn properties(&self, h_m: f64) -> SectionProperties {
        match *self {
            Section::BuiltUp(b) if h_m > 2.0 * b.skin_m => b.properties(h_m),
            _ => solid_properties(h_m),
        }
    }
}

/// Solid section of thickness h: A = h, I = h³/12, A_s = h, M_T/Δε = h²/12 (linear in z; Boley &
/// Weiner, Theory of Thermal Stresses, 1960, ch. 12).
fn solid_properties(h: f64) -> SectionProperties {
    SectionProperties {
        membrane_m: h,
        bending_m3: h.powi(3) / 12.0,
        shear_m: h,
        mass_m: h,
        rotary_m3: h.powi(3) / 12.0,
        thermal_moment_m2: h * h / 12.0,
    }
}

impl BuiltUp {
    /// Two skins t_s with centroids d = h − t_s apart and smeared webs w = w_spar + w_rib
    /// (Megson, Aircraft Structures for Engineering Students, 4th ed., ch. 15-16: the skins carry
    /// in-plane load and bending, the webs carry transverse shear):
    /// A = 2 t_s (webs carry no in-plane load),
    /// I = 2 t_s (d/2)² + t_s³/6 + (w/2) h³/12 (each web family stiffens one direction; the
    /// isotropic plate takes their mean), shear area (w/2) h (webs in pure shear),
    /// mass 2 t_s + w h, rotary 2 t_s (d/2)² + w h³/12, and the thermal moment of skins at
    /// ±d/2 whose free strains differ by Δε: M_T = E Δε t_s d/2.
    fn properties(&self, h: f64) -> SectionProperties {
        let t = self.skin_m;
        let d = h - t;
        let w = self.spar_web_ratio + self.rib_web_ratio;
        let skins = 2.0 * t * (0.5 * d).powi(2);
        SectionProperties {
            membrane_m: 2.0 * t,
            bending_m3: skins + t.powi(3) / 6.0 + 0.5 * w * h.powi(3) / 12.0,
            // The webs' G (w/2) h, stated before the solid section's κ the element applies.
            shear_m: 0.5 * w * h / SHEAR_CORRECTION,
            mass_m: 2.0 * t + w * h,
            rotary_m3: skins + w * h.powi(3) / 12.0,
            thermal_moment_m2: 0.5 * t * d,
        }
    }
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
    section: SectionProperties,
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
        let depth = (0..4).map(|k| n[k] * self.thickness_m[k]).sum();
        Point {
            n,
            dx,
            dy,
            jac,
            det,
            section: self.section.properties(depth),
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
/// K = ∫ B_bᵀ D_b B_b + B_sᵀ D_s B_s dA, D_b = E I C(ν), D_s = κ G A_s I (solid: I = t³/12,
/// A_s = t), with the shear
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
        let db = c * p.section.bending_m3;
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
        k += bs.transpose() * bs * (SHEAR_CORRECTION * g * p.section.shear_m * w);
    }
    k
}

/// Consistent bending-block mass: ρ ∫ m N_i N_j (w) + r N_i N_j (βx, βy) dA with the section's
/// mass m and rotary inertia r per ρ (solid: t and t³/12).
pub fn bending_mass(quad: &Quad, density_kg_m3: f64) -> Mat12 {
    let mut m = Mat12::zeros();
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let w = p.det.abs() * density_kg_m3;
        let rotary = p.section.rotary_m3;
        for i in 0..4 {
            for j in 0..4 {
                let nn = p.n[i] * p.n[j] * w;
                m[(3 * i, 3 * j)] += p.section.mass_m * nn;
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

/// Each corner's share of the element's section mass over ρ, ∫ N_i m dA (m³; exact for the
/// bilinear depth of a solid section).
pub fn node_mass_shares(quad: &Quad) -> [f64; 4] {
    let mut shares = [0.0; 4];
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        for (i, share) in shares.iter_mut().enumerate() {
            *share += p.n[i] * p.section.mass_m * p.det.abs();
        }
    }
    shares
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

/// Q4 membrane stiffness ∫ B_mᵀ (E A C(ν)) B_m dA (A: the section's in-plane area, solid t).
pub fn membrane_stiffness(quad: &Quad, e_pa: f64, nu: f64) -> Mat8 {
    let c = plane_stress(nu) * e_pa;
    let mut k = Mat8::zeros();
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let b = membrane_b(&p);
        k += b.transpose() * c * b * (p.section.membrane_m * p.det.abs());
    }
    k
}

/// Consistent membrane mass ρ ∫ m N_i N_j dA on u and on v (m: the section's mass per ρ).
pub fn membrane_mass(quad: &Quad, density_kg_m3: f64) -> Mat8 {
    let mut m = Mat8::zeros();
    for (s, t) in gauss_points() {
        let p = quad.point(s, t);
        let w = p.det.abs() * density_kg_m3 * p.section.mass_m;
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
/// `free` = ∫ A (1, 1, 0) dA, with A = E A_m C(ν) (A_m: the section's in-plane area); the
/// element-mean stress resultants are then
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
        let a = c * p.section.membrane_m;
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
/// Stresses, 1960, ch. 12, thin plates). A built-up section takes Δε between its skins
/// (lower minus upper) and M_T = E Δε t_s d/2 ([`SectionProperties::thermal_moment_m2`]).
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
        f += bb.transpose() * c * unit * (p.section.thermal_moment_m2 * p.det.abs());
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
            section: Section::Solid,
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
                p.det * p.section.mass_m
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
