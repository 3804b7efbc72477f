//! Root loads by force summation and thermal moments of `ritz-plate`, against statics,
//! Newton's second law and the free thermal curvature of plates. Each test names its source
//! and tolerance.

mod common;

use approx::assert_relative_eq;
use hsv_core::aero::Loads;
use hsv_core::material::Material;
use hsv_core::structure::StructureModel;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_model_ritz_plate::plate::PlateModel;
use hsv_model_ritz_plate::{RitzPlate, Settings};
use nalgebra::{DVector, Point3, Vector3};

const E: f64 = 70e9;
const NU: f64 = 0.3;
const RHO: f64 = 2700.0;
const ALPHA: f64 = 23e-6;

/// Aluminium-like constant material: α constant, so the face strain difference is α ΔT exactly.
fn constant_material() -> Material {
    Material::constant(
        "test alloy",
        RHO,
        NU,
        E,
        ALPHA,
        150.0,
        900.0,
        (100.0, 1000.0),
    )
    .expect("material")
}

fn sample_ritz(settings: &Settings) -> RitzPlate {
    let surface = hsv_core::config::LoadedConfig::sample()
        .expect("sample")
        .config
        .lifting_surface;
    let grid = SurfaceGrid::lifting_surface(
        &surface,
        hsv_core::geometry::Side::Right,
        settings.elements_chordwise,
        settings.elements_spanwise,
    )
    .expect("grid");
    RitzPlate::new(grid, Material::ti_6al_4v(), settings).expect("model")
}

/// Relative error of a load against the expected one, by the larger of force and moment.
fn load_error(got: &Loads, want: &Loads) -> (f64, f64) {
    (
        (got.force_n - want.force_n).norm() / want.force_n.norm(),
        (got.moment_nm - want.moment_nm).norm() / want.moment_nm.norm(),
    )
}

/// Statics of the free body of the surface (Newton's third law): a static point load F at the
/// mid-span leading edge of the sample surface is carried to the tube whole, so the load on
/// the tube is F and its moment about the pivot r × F (the tube's reaction on the surface is
/// −F, −r × F). Force summation with the reduced static solution K_r q = Φᵀ f (q̈ = 0) within
/// 1 % in force and moment (it is exact to round-off); the mode-displacement reactions
/// K_cf Φ q of the same 10 + 5 basis are printed for comparison (the point load is not in the
/// basis, so they converge slowly).
#[test]
fn force_summation_root_load_equals_a_static_point_load_at_the_leading_edge() {
    let model = sample_ritz(&Settings::default());
    let g = model.grid();
    let mid = g.nodes_spanwise() / 2;
    let node = g.node_index(0, mid);
    assert_relative_eq!(g.span_fractions[mid], 0.5, epsilon = 0.03);
    let force = Vector3::new(0.0, 0.0, -2.0e4);
    let mut nodal = vec![[0.0; 3]; g.n_nodes()];
    nodal[node][0] = force.z;
    let expected = Loads {
        force_n: force,
        moment_nm: (g.positions_m[node] - g.pivot_m).cross(&force),
    };
    // The resultant of nodal loads is the statics of the point load (1e-12).
    let applied = model.nodal_load_resultant(&nodal).expect("resultant");
    let (ef, em) = load_error(&applied, &expected);
    assert!(ef < 1e-12 && em < 1e-12, "{applied:?} vs {expected:?}");
    let q_gen = model
        .generalized_forces(&nodal)
        .expect("generalized forces");
    let q = model
        .modal_model()
        .stiffness
        .clone()
        .lu()
        .solve(&q_gen)
        .expect("static solve");
    let zero = DVector::zeros(q.len());
    // Through the capability the coupling uses.
    let summed = model
        .root_loads()
        .expect("root-load capability")
        .root_loads(&q, &zero, &zero, &applied)
        .expect("root loads");
    let (ef, em) = load_error(&summed, &expected);
    let displaced = model
        .root_loads_by_mode_displacement(&q, &zero, &zero)
        .expect("mode displacement");
    let (df, dm) = load_error(&displaced, &expected);
    eprintln!(
        "point load {force:?} at node {node} ({:?}): force summation {summed:?} (errors {ef:.1e}, \
         {em:.1e}); mode displacement {displaced:?} (errors {df:.2e}, {dm:.2e})",
        g.positions_m[node]
    );
    assert!(ef < 0.01 && em < 0.01, "force {ef}, moment {em}");
}

/// Newton's second law for the surface: with no applied load the load on the tube is minus
/// the rate of change of the elastic motion's momentum, F_z = −ρ ∫ t ẅ dA =
/// −ρ Σ_n V_n ẅ_n (V_n = ∫ N_n t dA, the grid's node volumes; exact for the consistent mass,
/// 1e-9), and the moments about the pivot −ρ ∫ t ẅ (y − y_p) dA and ρ ∫ t ẅ (x − x_p) dA plus the
/// rotary inertia ∓ρ ∫ t³/12 β̈ dA, integrated here independently with 3 × 3 Gauss points
/// (1e-9 on a rectangular plate; within 2e-4 of the moment on the sample surface, whose tapered
/// elements make the 2 × 2-point element mass inexact in its degree-4 terms).
#[test]
fn force_summation_inertia_is_the_rate_of_change_of_momentum() {
    let settings = Settings {
        elements_chordwise: 12,
        elements_spanwise: 10,
        ..Settings::default()
    };
    let rectangle = SurfaceGrid::rectangular(1.5, 2.0, 0.02, 12, 10).expect("grid");
    let rectangle = RitzPlate::new(rectangle, Material::ti_6al_4v(), &settings).expect("model");
    // Rectangular elements: the 2 × 2 mass quadrature is exact, so the moments agree to 1e-9.
    check_inertia_against_momentum(&rectangle, 1e-9);
    check_inertia_against_momentum(&sample_ritz(&settings), 2e-4);
}

fn check_inertia_against_momentum(model: &RitzPlate, moment_tolerance: f64) {
    let g = model.grid();
    let plate = model.plate();
    let rho = Material::ti_6al_4v().density_kg_m3;
    let r = model.basis().ncols();
    let pivot = g.pivot_m;
    let zero = DVector::zeros(r);
    for (c, accel) in [(0usize, 1.0), (3, -2.5), (12, 0.7)] {
        let mut qdd = DVector::zeros(r);
        qdd[c] = accel;
        let nodal_accel: Vec<f64> = model.basis().column(c).iter().map(|v| v * accel).collect();
        let value = |n: usize| plate.nodal_value(&nodal_accel, n);
        let loads = model
            .root_loads_by_force_summation(&zero, &zero, &qdd, &Loads::default())
            .expect("root loads");
        let fz: f64 = -rho
            * (0..g.n_nodes())
                .map(|n| g.node_volumes_m3[n] * value(n)[0])
                .sum::<f64>();
        let momentum_scale: f64 = rho
            * (0..g.n_nodes())
                .map(|n| g.node_volumes_m3[n] * value(n)[0].abs())
                .sum::<f64>();
        assert!((loads.force_n.z - fz).abs() < 1e-9 * momentum_scale);
        // Independent 3 × 3 Gauss integration of the momentum's moment over each element.
        let gp = [-(0.6f64.sqrt()), 0.0, 0.6f64.sqrt()];
        let gw = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let (mut mx, mut my) = (0.0, 0.0);
        for el in &g.elements {
            for (a, &s) in gp.iter().enumerate() {
                for (b, &t) in gp.iter().enumerate() {
                    let n: Vec<f64> = corners
                        .iter()
                        .map(|&(cs, ct)| 0.25 * (1.0 + cs * s) * (1.0 + ct * t))
                        .collect();
                    let ds: Vec<f64> = corners
                        .iter()
                        .map(|&(cs, ct)| 0.25 * cs * (1.0 + ct * t))
                        .collect();
                    let dt: Vec<f64> = corners
                        .iter()
                        .map(|&(cs, ct)| 0.25 * ct * (1.0 + cs * s))
                        .collect();
                    let sum = |f: &dyn Fn(usize) -> f64, w: &[f64]| -> f64 {
                        (0..4).map(|k| w[k] * f(el[k])).sum()
                    };
                    let x = |k: usize| g.positions_m[k].x;
                    let y = |k: usize| g.positions_m[k].y;
                    let det = sum(&x, &ds) * sum(&y, &dt) - sum(&y, &ds) * sum(&x, &dt);
                    let th = sum(&|k| g.thickness_m[k], &n);
                    let w = sum(&|k| value(k)[0], &n);
                    let bx = sum(&|k| value(k)[1], &n);
                    let by = sum(&|k| value(k)[2], &n);
                    let da = gw[a] * gw[b] * det.abs() * rho;
                    // Inertia force −ρ t ẅ ẑ at (x, y): moment (−(y − y_p) F, (x − x_p) F).
                    let f = -th * w * da;
                    mx += (sum(&y, &n) - pivot.y) * f + th.powi(3) / 12.0 * by * da;
                    my += -(sum(&x, &n) - pivot.x) * f - th.powi(3) / 12.0 * bx * da;
                }
            }
        }
        let scale = loads.moment_nm.norm();
        eprintln!(
            "q̈[{c}] = {accel}: F_z {:.6e} (ρΣVẅ {fz:.6e}), M_x {:.6e} ({mx:.6e}), M_y {:.6e} ({my:.6e})",
            loads.force_n.z, loads.moment_nm.x, loads.moment_nm.y
        );
        assert!((loads.moment_nm.x - mx).abs() < moment_tolerance * scale);
        assert!((loads.moment_nm.y - my).abs() < moment_tolerance * scale);
        assert!(loads.force_n.x == 0.0 && loads.force_n.y == 0.0 && loads.moment_nm.z == 0.0);
    }
}

/// Under a uniform pressure the 10 + 5 basis contains the static solution, so the two root-load
/// methods must agree on the free nodes' share; force summation adds the root row's own share,
/// which goes straight to the tube: F_z = p S over the whole planform, M = Σ r × F about the
/// pivot (statics, 1e-6).
#[test]
fn force_summation_includes_the_root_rows_share_of_a_uniform_pressure() {
    let model = sample_ritz(&Settings::default());
    let g = model.grid();
    let p = 5.0e4;
    let nodal: Vec<[f64; 3]> = g.node_areas_m2.iter().map(|a| [p * a, 0.0, 0.0]).collect();
    let q_gen = model.generalized_forces(&nodal).expect("forces");
    let q = model
        .modal_model()
        .stiffness
        .clone()
        .lu()
        .solve(&q_gen)
        .expect("solve");
    let zero = DVector::zeros(q.len());
    let applied = model.nodal_load_resultant(&nodal).expect("resultant");
    let summed = model
        .root_loads_by_force_summation(&q, &zero, &zero, &applied)
        .expect("loads");
    assert_relative_eq!(
        summed.force_n.z,
        p * g.planform_area_m2(),
        max_relative = 1e-9
    );
    let root_share = |f: &dyn Fn(usize) -> f64| -> f64 { g.root_nodes.iter().map(|&n| f(n)).sum() };
    let displaced = model
        .root_loads_by_mode_displacement(&q, &zero, &zero)
        .expect("loads");
    let root_fz = root_share(&|n| p * g.node_areas_m2[n]);
    let root_mx = root_share(&|n| (g.positions_m[n].y - g.pivot_m.y) * p * g.node_areas_m2[n]);
    let root_my = root_share(&|n| -(g.positions_m[n].x - g.pivot_m.x) * p * g.node_areas_m2[n]);
    assert_relative_eq!(
        summed.force_n.z,
        displaced.force_n.z + root_fz,
        max_relative = 1e-6
    );
    assert_relative_eq!(
        summed.moment_nm.x,
        displaced.moment_nm.x + root_mx,
        max_relative = 1e-6
    );
    assert_relative_eq!(
        summed.moment_nm.y,
        displaced.moment_nm.y + root_my,
        max_relative = 1e-6
    );
}

/// The left surface's force-summation root load is the mirror image of the right's (F_y, M_x,
/// M_z change sign) about the mirrored pivot.
#[test]
fn left_side_force_summation_mirrors_the_right() {
    let right = sample_ritz(&Settings {
        elements_chordwise: 8,
        elements_spanwise: 6,
        ..Settings::default()
    });
    let left = right.clone().with_side(hsv_core::geometry::Side::Left);
    let pr = right.root_reference_m();
    let pl = left.root_reference_m();
    assert_eq!(pl, Point3::new(pr.x, -pr.y, pr.z));
    let qdd = DVector::from_fn(15, |i, _| 0.1 * (i as f64 + 1.0));
    let zero = DVector::zeros(15);
    let a = right
        .root_loads_by_force_summation(&zero, &zero, &qdd, &Loads::default())
        .unwrap();
    let b = left
        .root_loads_by_force_summation(&zero, &zero, &qdd, &Loads::default())
        .unwrap();
    assert_relative_eq!(a.force_n.z, b.force_n.z);
    assert_relative_eq!(a.moment_nm.x, -b.moment_nm.x);
    assert_relative_eq!(a.moment_nm.y, b.moment_nm.y);
    assert!(a.moment_nm.x.abs() > 0.0 && a.force_n.z.abs() > 0.0);
    let e = right
        .root_loads_by_force_summation(&zero, &DVector::zeros(3), &qdd, &Loads::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("3 modal velocities"), "{e}");
    let e = right
        .generalized_forces(&[[0.0; 3]; 4])
        .unwrap_err()
        .to_string();
    assert!(e.contains("4 nodal loads"), "{e}");
}

/// Mid-plane and through-thickness temperatures for a linear ΔT: faces at 293 ∓ ΔT/2 K.
fn linear_through_thickness(n: usize, dt_k: f64) -> (Vec<f64>, Vec<f64>) {
    (vec![293.0; n], vec![dt_k; n])
}

/// A plate free to bend (w held at three corners only: statically determinate) under a linear
/// through-thickness temperature difference ΔT (lower face hotter) bends stress-free to the
/// spherical curvature κ_x = κ_y = α ΔT / t (Boley & Weiner, Theory of Thermal Stresses, 1960,
/// thin plates: a linear temperature through the thickness of an unrestrained plate gives no
/// stress), w = −κ (x² + y²)/2 + rigid motion (z down). Full-order model, 10 × 10 mesh of a
/// 1 m × 0.6 m × 10 mm plate, ΔT = 20 K: curvatures from nodal second differences and the
/// rotations β = κ (x, y) within 1e-6, reactions zero.
#[test]
fn free_plate_bends_to_the_free_thermal_curvature() {
    let (c, s, h, dt) = (1.0, 0.6, 0.01, 20.0);
    let grid = SurfaceGrid::rectangular(c, s, h, 10, 10).expect("grid");
    let supports = common::three_corner_supports(&grid);
    let plate = PlateModel::new(grid, constant_material(), supports).expect("plate");
    let (mean, diff) = linear_through_thickness(plate.grid.n_nodes(), dt);
    let kappa = ALPHA * dt / h;
    let bent = common::free_thermal_bending(&plate, &mean, &diff, kappa, (c, s));
    let worst = bent.worst_curvature.max(bent.worst_rotation_gradient);
    eprintln!("free plate: κ_T = α ΔT / t = {kappa:.6e} 1/m; worst relative error {worst:.2e}");
    assert!(worst < 1e-6, "{worst}");
    // Self-equilibrated load on a statically determinate support: no reactions.
    assert!(bent.net_load_ratio < 1e-10, "{}", bent.net_load_ratio);
}

/// A cantilever strip (root clamped, the rest free) under a linear through-thickness ΔT: away
/// from the root the moments vanish, so the strip takes the free curvature κ = α ΔT / t along
/// the span (Boley & Weiner 1960), w = −κ y²/2 plus a root correction that decays within about
/// a chord. Rectangular planform 0.2 m × 1 m × 10 mm, 4 × 40 mesh, ΔT = 20 K. Full order: the
/// spanwise curvature at mid-chord over 0.4-0.95 of the span within 1 %. Ritz model with the
/// generalized thermal force Q_T = Φᵀ f_T: the paper's 10 + 5 basis gets the tip deflection of
/// the full model within 1 % (its local curvature is printed: a truncated basis converges slowly
/// in curvature); with `thermal_moment_shape` the response is in the basis and the curvature
/// is within 1 % of κ. No root load either way (the thermal load is self-equilibrated).
#[test]
fn cantilever_strip_curls_to_the_free_thermal_curvature() {
    let (c, s, h, dt) = (0.2, 1.0, 0.01, 20.0);
    let kappa = ALPHA * dt / h;
    for thermal_moment_shape in [false, true] {
        let settings = Settings {
            elements_chordwise: 4,
            elements_spanwise: 40,
            thermal_moment_shape,
            ..Settings::default()
        };
        let grid = SurfaceGrid::rectangular(c, s, h, 4, 40).expect("grid");
        let n = grid.n_nodes();
        let mut model = RitzPlate::new(grid, constant_material(), &settings).expect("model");
        let (mean, diff) = linear_through_thickness(n, dt);
        model
            .set_temperature_field(&mean, &diff)
            .expect("temperatures");
        // Full order: K u = f_T at 293 K (the mean temperature is the reference: E, no stress).
        let plate = model.plate();
        let (_, full) = common::thermal_moment_displacements(plate, &mean, &diff);
        // Reduced: K_r q = Q_T.
        let q = model
            .modal_model()
            .stiffness
            .clone()
            .lu()
            .solve(model.thermal_generalized_forces())
            .expect("solve");
        let reduced: Vec<f64> = (model.basis() * &q).iter().copied().collect();
        let g = model.grid();
        let dy = s / 40.0;
        let curvature = |u: &[f64], j: usize| -> f64 {
            let w = |j: usize| plate.nodal_value(u, g.node_index(2, j))[0];
            -(w(j + 1) - 2.0 * w(j) + w(j - 1)) / (dy * dy)
        };
        let (mut worst_full, mut worst_ritz): (f64, f64) = (0.0, 0.0);
        for j in 16..=38 {
            worst_full = worst_full.max((curvature(&full, j) / kappa - 1.0).abs());
            worst_ritz = worst_ritz.max((curvature(&reduced, j) / kappa - 1.0).abs());
        }
        let tip = |u: &[f64]| plate.nodal_value(u, g.node_index(2, 40))[0];
        eprintln!(
            "strip (thermal shape {thermal_moment_shape}): κ_T = {kappa:.6e} 1/m; worst spanwise \
             curvature error full {worst_full:.2e}, Ritz {worst_ritz:.2e}; tip w full {:.6e} m, \
             Ritz {:.6e} m, −κ L²/2 = {:.6e} m",
            tip(&full),
            tip(&reduced),
            -0.5 * kappa * s * s
        );
        assert!(worst_full < 0.01, "{worst_full}");
        assert_relative_eq!(tip(&reduced), tip(&full), max_relative = 0.01);
        if thermal_moment_shape {
            assert!(worst_ritz < 0.01, "{worst_ritz}");
        }
        let zero = DVector::zeros(q.len());
        let root = model
            .root_loads_by_force_summation(&q, &zero, &zero, &Loads::default())
            .expect("root");
        assert!(root.force_n.norm() == 0.0 && root.moment_nm.norm() == 0.0);
    }
}

/// Bad through-thickness input is an error naming the quantity, the node and the count.
#[test]
fn bad_through_thickness_differences_name_the_quantity() {
    let grid = SurfaceGrid::rectangular(1.0, 1.0, 0.01, 4, 4).expect("grid");
    let n = grid.n_nodes();
    let settings = Settings {
        free_vibration_modes: 3,
        static_shapes: 2,
        elements_chordwise: 4,
        elements_spanwise: 4,
        ..Settings::default()
    };
    let mut model = RitzPlate::new(grid, constant_material(), &settings).expect("model");
    let e = model
        .set_temperature_field(&vec![300.0; n], &vec![0.0; n - 1])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!(
            "{} through-thickness temperature differences",
            n - 1
        )),
        "{e}"
    );
    let mut d = vec![0.0; n];
    d[3] = f64::INFINITY;
    let e = model
        .set_temperature_field(&vec![300.0; n], &d)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("through-thickness temperature difference") && e.contains("node 3"),
        "{e}"
    );
    // A face beyond the material data (constant material: 100-1000 K).
    let e = model
        .set_temperature_field(&vec![900.0; n], &vec![400.0; n])
        .unwrap_err()
        .to_string();
    assert!(e.contains("1100"), "{e}");
}
