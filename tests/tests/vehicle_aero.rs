//! Whole-vehicle aero through the `hsv-run` library: every registered aero model on the sample
//! vehicle obeys the symmetry of a vehicle with a plane of symmetry (Etkin, Dynamics of Flight,
//! §5.2: at zero sideslip and zero roll/yaw rates the lateral force and moments vanish), and the
//! engine-owned surfaces are integrated only when asked for.

use hsv_core::config::LoadedConfig;
use hsv_run::aero_job::{self, AeroRequest};

fn request(models: Vec<String>, alpha_deg: f64, beta_deg: f64, engine: bool) -> AeroRequest {
    let loaded = LoadedConfig::sample().expect("sample config");
    AeroRequest {
        mach: 6.0,
        altitude_m: 26_000.0,
        alpha_deg,
        beta_deg,
        models,
        reference: loaded.config.reference,
        include_engine_surfaces: engine,
    }
}

#[test]
fn symmetric_vehicle_has_no_lateral_loads_at_zero_sideslip() {
    let loaded = LoadedConfig::sample().unwrap();
    let registry = hsv_run::registry().unwrap();
    let mesh = aero_job::vehicle_mesh(&loaded).unwrap();
    let models = aero_job::all_aero_models(&registry);
    for alpha in [-2.0, 0.0, 3.0] {
        let rows = aero_job::run_aero(
            &loaded,
            &registry,
            &mesh,
            &request(models.clone(), alpha, 0.0, false),
        )
        .unwrap();
        for row in rows {
            let f = row.loads.force_n;
            let m = row.loads.moment_nm;
            let scale = f.norm().max(1.0);
            // Round-off of a sum over ~1700 panels: relative 1e-10.
            assert!(
                f.y.abs() < 1e-10 * scale,
                "{} alpha {alpha}: Fy {}",
                row.model,
                f.y
            );
            assert!(
                m.x.abs() < 1e-10 * scale * 30.0,
                "{}: Mx {}",
                row.model,
                m.x
            );
            assert!(
                m.z.abs() < 1e-10 * scale * 30.0,
                "{}: Mz {}",
                row.model,
                m.z
            );
        }
    }
}

#[test]
fn sideslip_gives_a_side_force_opposing_it() {
    // Positive sideslip: the air comes from the right (+y), pushing the vehicle to -y.
    let loaded = LoadedConfig::sample().unwrap();
    let registry = hsv_run::registry().unwrap();
    let mesh = aero_job::vehicle_mesh(&loaded).unwrap();
    let rows = aero_job::run_aero(
        &loaded,
        &registry,
        &mesh,
        &request(
            vec!["shock-expansion".into(), "newtonian-scalar".into()],
            0.0,
            2.0,
            false,
        ),
    )
    .unwrap();
    for row in rows {
        assert!(
            row.loads.force_n.y < 0.0,
            "{}: Fy {}",
            row.model,
            row.loads.force_n.y
        );
    }
}

#[test]
fn engine_surfaces_are_counted_only_on_request() {
    let loaded = LoadedConfig::sample().unwrap();
    let registry = hsv_run::registry().unwrap();
    let mesh = aero_job::vehicle_mesh(&loaded).unwrap();
    let model = vec!["shock-expansion".to_owned()];
    let without = aero_job::run_aero(
        &loaded,
        &registry,
        &mesh,
        &request(model.clone(), 0.0, 0.0, false),
    )
    .unwrap();
    let with =
        aero_job::run_aero(&loaded, &registry, &mesh, &request(model, 0.0, 0.0, true)).unwrap();
    // The 6.2 deg inlet ramp faces down into the flow: adding it adds upward (-z) force.
    assert!(with[0].loads.force_n.z < without[0].loads.force_n.z);
}
