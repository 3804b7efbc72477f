//! Mass properties and rigid-body coupling of the beam against closed forms for a rod of two
//! uniform segments (paper Table 1: μ_f = 838 kg/m over L_f = 15.2 m, μ_a = 1250 kg/m over
//! L_a = 15.2 m, I_x = 3.28e3 kg m²/m).

use hsv_core::registry::ModelContext;
use hsv_core::structure::StructureModel;
use hsv_model_free_free_beam::FreeFreeBeam;

fn sample_beam() -> FreeFreeBeam {
    let region = hsv_core::testing::sample_region("main_body");
    let settings = region.model_settings("free-free-beam");
    let ctx = ModelContext::new(region, hsv_core::testing::empty_registry(), &settings);
    FreeFreeBeam::from_context(&ctx).expect("sample beam")
}

#[test]
fn mass_centre_and_inertia_match_the_two_segment_rod() {
    let beam = sample_beam();
    let props = beam
        .mass_properties()
        .expect("capability")
        .mass_properties();
    let (mu_f, mu_a, l_f, l_a, i_x) = (838.0, 1250.0, 15.2, 15.2, 3.28e3);
    // Closed form: m = Σ μ L; x_G = −Σ μ L s_c / m (s aft of the nose); I_yy = I_zz =
    // Σ (μ L³/12 + μ L (s_c − s_G)²); I_xx = I_x (L_f + L_a).
    let m = mu_f * l_f + mu_a * l_a;
    let s_g = (mu_f * l_f * (l_f / 2.0) + mu_a * l_a * (l_f + l_a / 2.0)) / m;
    let segment = |mu: f64, l: f64, s_c: f64| mu * l.powi(3) / 12.0 + mu * l * (s_c - s_g).powi(2);
    let i_yy = segment(mu_f, l_f, l_f / 2.0) + segment(mu_a, l_a, l_f + l_a / 2.0);
    let i_xx = i_x * (l_f + l_a);
    // The consistent Hermite mass matrix integrates rigid motions exactly: 1e-9 relative.
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1.0);
    assert!(close(props.mass_kg, m), "{} vs {m}", props.mass_kg);
    assert!(
        close(-props.center_of_mass_m.x, s_g),
        "{:?}",
        props.center_of_mass_m
    );
    let i = props.inertia_kg_m2;
    assert!(close(i[(1, 1)], i_yy), "I_yy {} vs {i_yy}", i[(1, 1)]);
    assert!(close(i[(2, 2)], i_yy), "I_zz {} vs {i_yy}", i[(2, 2)]);
    assert!(close(i[(0, 0)], i_xx), "I_xx {} vs {i_xx}", i[(0, 0)]);
    assert!(i[(0, 1)].abs() + i[(0, 2)].abs() + i[(1, 2)].abs() < 1e-9 * i_yy);
}

#[test]
fn free_free_modes_do_not_couple_with_rigid_motion() {
    // Elastic modes of a free-free structure are mass-orthogonal to its rigid-body motions
    // (Meirovitch, Fundamentals of Vibrations, §7.5), so Φᵀ M R = 0.
    let beam = sample_beam();
    let coupling = beam.rigid_body_coupling().expect("capability");
    let c = coupling.rigid_coupling();
    assert_eq!(c.ncols(), 6);
    let scale = beam
        .mass_properties()
        .expect("mass")
        .mass_properties()
        .mass_kg
        .sqrt()
        * 30.4;
    assert!(c.amax() < 1e-8 * scale, "max |Φᵀ M R| = {}", c.amax());
}
