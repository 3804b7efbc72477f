//! Flow fixtures and the van Driest II reference shared by the Eckert test files.
#![allow(dead_code)] // each test binary uses a subset

use hsv_core::aero::{AeroSolution, EdgeState};
use hsv_core::atmosphere::sutherland_viscosity;
use hsv_core::flow::Freestream;
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::PanelMesh;

pub fn freestream(mach: f64, altitude_m: f64) -> Freestream {
    Freestream::standard(mach, altitude_m, PerfectGas::AIR).expect("standard atmosphere")
}

/// The undisturbed freestream as a boundary-layer edge (a flat plate at zero incidence).
pub fn edge_of(f: &Freestream) -> EdgeState {
    EdgeState {
        mach: f.mach,
        pressure_pa: f.pressure_pa,
        temperature_k: f.temperature_k,
        density_kg_m3: f.density_kg_m3,
        velocity_m_s: f.velocity_m_s,
    }
}

/// An aero solution with the same edge state on every panel of `mesh`.
pub fn uniform_solution(mesh: &PanelMesh, edge: EdgeState) -> AeroSolution {
    let mut aero = AeroSolution::default();
    aero.reset(mesh.panels.len());
    aero.edge.fill(edge);
    aero
}

/// Van Driest II local skin friction at edge Reynolds number `re_x` (NASA Langley Turbulence
/// Modeling Resource, ZPG flat plate theory): C_f = C_f,inc(Re_θ μ_e/μ_w)/F_c, C_f,inc(Re) =
/// 1/(17.08 log²Re + 25.11 log Re + 6.012), F_c = (T_aw/T_e − 1)/(asin A + asin B)², with
/// a = √(r (γ−1)/2 M² T_e/T_w), b = T_aw/T_w − 1, A = (2a² − b)/√(b² + 4a²), B = b/√(b² + 4a²);
/// Re_x from dRe_x/dRe_θ = 2/C_f (momentum integral, zero pressure gradient).
pub fn van_driest_ii_skin_friction(te: f64, tw: f64, mach: f64, r: f64, re_x: f64) -> f64 {
    // Adiabatic wall, T_aw = T_e (1 + r (γ − 1)/2 M²), γ = 1.4.
    let taw = te * (1.0 + r * 0.2 * mach * mach);
    let a = (r * 0.2 * mach * mach * te / tw).sqrt();
    let b = taw / tw - 1.0;
    let q = (b * b + 4.0 * a * a).sqrt();
    let fc = (taw / te - 1.0) / (((2.0 * a * a - b) / q).asin() + (b / q).asin()).powi(2);
    let mu_ratio = sutherland_viscosity(te) / sutherland_viscosity(tw);
    let cf = |re_theta: f64| {
        let l = (re_theta * mu_ratio).log10();
        1.0 / (17.08 * l * l + 25.11 * l + 6.012) / fc
    };
    // Integrate Re_x(Re_θ) on a log grid from Re_θ = 100 (its Re_x is negligible at 1e7).
    let mut re_theta: f64 = 100.0;
    let mut x = 2.0 * re_theta / cf(re_theta);
    let ratio: f64 = 1.001;
    loop {
        let next = re_theta * ratio;
        let dx = (next - re_theta) * (1.0 / cf(re_theta) + 1.0 / cf(next));
        if x + dx >= re_x {
            let t = (re_x - x) / dx;
            return cf(re_theta + t * (next - re_theta));
        }
        x += dx;
        re_theta = next;
    }
}
