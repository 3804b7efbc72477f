//! Strips across a span: a strip whose panels are inclined as the strip before it (to 1e-12
//! rad) takes that strip's march, and any other strip is marched on its own. Checked on wedge
//! strips against the weak oblique shock (NACA 1135 eq. 150, `hsv_core::gas::oblique_shock`)
//! and Prandtl-Meyer expansion back to the freestream direction (`prandtl_meyer_expansion`).

use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion};
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::{self, PerfectGas, ShockBranch};
use hsv_core::mesh::{PanelMesh, RegionKind, Surface};
use hsv_model_shock_expansion::ShockExpansion;

mod common;

const MACH: f64 = 6.0;

/// Lower-surface strips side by side at y = 0, 1, 2, ..., each a wedge of `angles_rad[k]`
/// over its first half chord and flat behind it (unit chord, leading edge at x = 0).
fn wedge_strips(angles_rad: &[f64]) -> PanelMesh {
    let mut vertices = Vec::new();
    let mut panels = Vec::new();
    let mut strips = Vec::new();
    for (k, &angle) in angles_rad.iter().enumerate() {
        let rise = 0.5 * angle.tan();
        common::push_extruded_strip(
            (&mut vertices, &mut panels, &mut strips),
            &[(0.0, 0.0), (-0.5, rise), (-1.0, rise)],
            k as f64,
            true,
        );
    }
    PanelMesh::new(
        vertices,
        &panels,
        strips,
        vec![Surface::new("wedges", RegionKind::LiftingSurface)],
    )
    .expect("valid wedge mesh")
}

fn evaluate(mesh: &PanelMesh) -> (AeroSolution, Freestream) {
    let freestream = Freestream::standard(MACH, 20_000.0, PerfectGas::AIR).expect("atmosphere");
    let flight = FlightCondition::steady(freestream, 0.0, 0.0);
    let mut out = AeroSolution::default();
    ShockExpansion::new()
        .evaluate(mesh, &flight, &PanelMotion::default(), &mut out)
        .expect("evaluation");
    (out, freestream)
}

/// Pressures behind a wedge of `angle_rad` and after turning back to the freestream
/// direction, Pa.
fn wedge_pressures(freestream: &Freestream, angle_rad: f64) -> (f64, f64) {
    let gamma = freestream.gas.gamma;
    let shock = gas::oblique_shock(MACH, angle_rad, gamma, ShockBranch::Weak).expect("attached");
    let p_wedge = freestream.pressure_pa * shock.pressure_ratio;
    let expansion =
        gas::prandtl_meyer_expansion(shock.mach_downstream, angle_rad, gamma).expect("expansion");
    (p_wedge, p_wedge * expansion.pressure_ratio)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs()
}

#[test]
fn identical_strips_share_the_march_and_a_different_one_is_marched_alone() {
    let angle = 5f64.to_radians();
    // Strips 1 and 2 repeat strip 0; strip 3's wedge is 1e-6 rad steeper, a millionth of a
    // radian beyond the repeat tolerance; strip 4 repeats strip 3.
    let angles = [angle, angle, angle, angle + 1e-6, angle + 1e-6];
    let mesh = wedge_strips(&angles);
    let (out, freestream) = evaluate(&mesh);
    for (k, strip) in mesh.strips.iter().enumerate() {
        let (wedge, behind) = wedge_pressures(&freestream, angles[k]);
        let (p0, p1) = (
            out.pressure_pa[strip.panels[0]],
            out.pressure_pa[strip.panels[1]],
        );
        assert!(
            close(p0, wedge),
            "strip {k}: wedge {p0} Pa vs oblique shock {wedge} Pa"
        );
        assert!(
            close(p1, behind),
            "strip {k}: behind {p1} Pa vs expansion {behind} Pa"
        );
    }
    // The steeper wedge's pressure is its own: about 1e-5 relative above the others'.
    let (p_first, p_steep) = (
        out.pressure_pa[0],
        out.pressure_pa[mesh.strips[3].panels[0]],
    );
    assert!(
        (p_steep - p_first) / p_first > 1e-6,
        "{p_steep} Pa vs {p_first} Pa"
    );
}
