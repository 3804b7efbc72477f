//! The `pod` model against the `full-order` model it reduces, on the sample lifting surface.
//!
//! Heating: a convective boundary condition q = h(x) (T_aw − T_w) − ε σ T_w⁴ with the
//! flat-plate laminar decay h = h_ref (1 m / x)^(1/2) along the running length x from the
//! leading edge (Anderson, Hypersonic and High-Temperature Gas Dynamics §6.9: St ∝ Re_x^(−1/2)),
//! so each "flight condition" is a pair (T_aw, h_ref). Snapshots come from three conditions; the
//! check is a fourth condition between them, not in the snapshots. T_aw stays below 923 K,
//! where the Ti-6Al-4V c_p is linear and k nearly so (the model's line fits).

mod common;

use std::sync::OnceLock;

use common::{convective, full_order, lifting, mesh, running_lengths};
use hsv_core::mesh::PanelMesh;
use hsv_core::registry::{ModelContext, Registry};
use hsv_core::thermal::ConductionModel;
use hsv_model_conduction::{FullOrderSettings, Pod, PodBasis, PodSettings, collect_snapshots};
use nalgebra::DVector;

const DT: f64 = 0.5;
const STEPS: usize = 120;

/// Snapshots of three conditions, every step of 0.5 s for 60 s (360 snapshots).
fn snapshots() -> &'static Vec<DVector<f64>> {
    static SNAPSHOTS: OnceLock<Vec<DVector<f64>>> = OnceLock::new();
    SNAPSHOTS.get_or_init(|| {
        let cfg = lifting();
        let x = running_lengths(&mesh(), &cfg);
        let mut model = full_order();
        let mut all = Vec::new();
        for (t_aw, h_ref) in [(900.0, 50.0), (700.0, 120.0), (800.0, 80.0)] {
            let mut flux = convective(&x, t_aw, h_ref);
            all.extend(
                collect_snapshots(&mut model, 293.0, DT, STEPS, 1, |w, q| {
                    flux(w, q);
                    Ok(())
                })
                .unwrap(),
            );
        }
        all
    })
}

fn basis(modes: usize) -> PodBasis {
    PodBasis::from_snapshots(snapshots(), modes, FullOrderSettings::default()).unwrap()
}

/// The paper's 32 modes capture all but ~1e-6 of the snapshot energy.
#[test]
fn thirty_two_modes_capture_the_snapshot_energy() {
    let b = basis(32);
    println!(
        "energy fraction {:.9}, sigma_1 {:.3e}, sigma_31 {:.3e}",
        b.energy_fraction, b.singular_values[0], b.singular_values[30]
    );
    assert!(b.energy_fraction > 0.99999, "{}", b.energy_fraction);
    assert!(b.energy_fraction <= 1.0);
    // Orthonormal, mode 0 uniform.
    let gram = b.modes.transpose() * &b.modes;
    for i in 0..32 {
        for j in 0..32 {
            let expected = if i == j { 1.0 } else { 0.0 };
            assert!((gram[(i, j)] - expected).abs() < 1e-10);
        }
    }
    let n = b.modes.nrows() as f64;
    assert!(
        b.modes
            .column(0)
            .iter()
            .all(|v| (v - 1.0 / n.sqrt()).abs() < 1e-12)
    );
    // More modes capture more.
    assert!(basis(8).energy_fraction < b.energy_fraction);
}

/// POD (32 modes) against the full-order model at a condition not in the snapshots
/// (T_aw = 850 K, h_ref = 65 W/(m² K)), 60 s: the largest temperature difference anywhere in
/// the structure stays below 1 % of the largest temperature rise.
#[test]
fn pod_reproduces_the_full_order_model_off_the_snapshots() {
    let cfg = lifting();
    let mesh = mesh();
    let x = running_lengths(&mesh, &cfg);
    let mut full = full_order();
    let mut pod = Pod::new(&full, basis(32), PodSettings::default()).unwrap();
    let mut t_full = full.uniform_state(293.0).unwrap();
    let mut a = pod.uniform_state(293.0).unwrap();
    let n = mesh.panels.len();
    let (mut wall_full, mut wall_pod) = (vec![0.0; n], vec![0.0; n]);
    let (mut q_full, mut q_pod) = (vec![0.0; n], vec![0.0; n]);
    let mut flux = convective(&x, 850.0, 65.0);
    let mut worst: f64 = 0.0;
    let mut rise: f64 = 0.0;
    for _ in 0..STEPS {
        full.surface_temperatures(&t_full, &mut wall_full);
        pod.surface_temperatures(&a, &mut wall_pod);
        flux(&wall_full, &mut q_full);
        flux(&wall_pod, &mut q_pod);
        full.step(&mut t_full, &q_full, DT).unwrap();
        pod.step(&mut a, &q_pod, DT).unwrap();
        let reconstructed = pod.reconstruct(&a);
        worst = worst.max((reconstructed - &t_full).amax());
        rise = rise.max(t_full.max() - 293.0);
    }
    println!("largest |T_pod - T_full| = {worst:.4} K, largest rise {rise:.1} K");
    assert!(rise > 100.0);
    assert!(worst < 0.01 * rise, "{worst} K vs rise {rise} K");
    // Node and surface outputs agree too.
    let mut nodes_full = vec![0.0; full.n_nodes()];
    let mut nodes_pod = vec![0.0; pod.n_nodes()];
    full.node_temperatures(&t_full, &mut nodes_full);
    pod.node_temperatures(&a, &mut nodes_pod);
    for (f, p) in nodes_full.iter().zip(&nodes_pod) {
        assert!((f - p).abs() < 0.01 * rise);
    }
}

#[test]
fn a_snapshot_set_smaller_than_the_mode_count_is_an_error() {
    let few: Vec<DVector<f64>> = snapshots()[..10].to_vec();
    let err = PodBasis::from_snapshots(&few, 32, FullOrderSettings::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("10 snapshots") && err.contains("32 modes"),
        "{err}"
    );
}

/// The basis survives a JSON round trip, and the registered `pod` loads it by its settings;
/// a basis built for other full-order settings or a missing file are clear errors.
#[test]
fn basis_is_saved_and_reloaded_by_the_registered_model() {
    let b = basis(12);
    let dir = std::env::temp_dir().join(format!("hsv-pod-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("basis.json");
    b.save(&path).unwrap();
    let back = PodBasis::load(&path).unwrap();
    assert_eq!(back.modes.shape(), b.modes.shape());
    assert!((back.modes.clone() - &b.modes).amax() < 1e-15);
    assert_eq!(back.singular_values.len(), b.singular_values.len());

    let mut settings = toml::Table::new();
    settings.insert(
        "basis_file".into(),
        toml::Value::String(path.display().to_string()),
    );
    settings.insert("modes".into(), toml::Value::Integer(12));
    let registry = Registry::builtin().unwrap();
    let model = registry
        .create::<dyn hsv_core::thermal::ConductionModel>(
            "pod",
            &common::sample_context(&settings, "models.pod"),
        )
        .unwrap();
    assert_eq!(model.n_states(), 12);
    let state = model.uniform_state(293.0).unwrap();
    let mut nodes = vec![0.0; model.n_nodes()];
    model.node_temperatures(&state, &mut nodes);
    assert!(nodes.iter().all(|t| (t - 293.0).abs() < 1e-9));

    // Too many modes for the basis.
    settings.insert("modes".into(), toml::Value::Integer(40));
    let err = registry
        .create::<dyn hsv_core::thermal::ConductionModel>(
            "pod",
            &common::sample_context(&settings, "models.pod"),
        )
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("modes") && err.contains("12"), "{err}");
    settings.insert("modes".into(), toml::Value::Integer(12));

    // A basis for another grid: this region's full-order grid is coarser.
    let mut other = hsv_core::testing::sample_region("right_surface").clone();
    let mut fo = other.model_settings("full-order");
    fo.table
        .insert("elements_spanwise".into(), toml::Value::Integer(6));
    other.settings.insert("full-order".into(), fo);
    let err = registry
        .create::<dyn hsv_core::thermal::ConductionModel>(
            "pod",
            &ModelContext {
                region: &other,
                ..common::sample_context(&settings, "models.pod")
            },
        )
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("basis"), "{err}");

    // No basis file.
    std::fs::remove_file(&path).unwrap();
    let err = registry
        .create::<dyn hsv_core::thermal::ConductionModel>(
            "pod",
            &common::sample_context(&settings, "models.pod"),
        )
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("models.pod.basis_file") && err.contains("does not exist"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Heat flux q = 1e5 (T_ref − T_w) / 300 K W/m² with T_ref = 1200 K: a test stand-in for a
/// registered heat-flux model.
struct RelaxingFlux;

impl hsv_core::thermal::HeatFluxModel for RelaxingFlux {
    fn name(&self) -> &str {
        "relaxing-flux"
    }
    fn heat_flux(
        &mut self,
        _mesh: &PanelMesh,
        _flight: &hsv_core::flow::FlightCondition,
        _aero: &hsv_core::aero::AeroSolution,
        wall_temperature_k: &[f64],
        out_w_m2: &mut [f64],
    ) -> Result<(), hsv_core::ModelError> {
        for (q, t) in out_w_m2.iter_mut().zip(wall_temperature_k) {
            *q = 1e5 * (1200.0 - t) / 300.0;
        }
        Ok(())
    }
}

/// Freestream pressure on every panel: a test stand-in for a registered aero model.
struct FreestreamAero;

impl hsv_core::aero::AeroModel for FreestreamAero {
    fn name(&self) -> &str {
        "freestream-aero"
    }
    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &hsv_core::flow::FlightCondition,
        _motion: &hsv_core::aero::PanelMotion<'_>,
        out: &mut hsv_core::aero::AeroSolution,
    ) -> Result<(), hsv_core::ModelError> {
        out.reset(mesh.panels.len());
        out.pressure_pa.fill(flight.freestream.pressure_pa);
        Ok(())
    }
}

/// The built-in models plus the two stand-ins.
fn training_registry() -> Registry {
    use hsv_core::registry::{Factory, Origin, RegistryEntry};
    use std::sync::Arc;
    let mut registry = Registry::builtin().unwrap();
    let entry = |name: &str, factory: Factory| RegistryEntry {
        name: name.to_owned(),
        fidelity: 0,
        summary: String::new(),
        settings_doc: String::new(),
        origin: Origin::BuiltIn("pod test".to_owned()),
        factory,
    };
    registry
        .insert(entry(
            "relaxing-flux",
            Factory::HeatFlux(Arc::new(|_| Ok(Box::new(RelaxingFlux)))),
        ))
        .unwrap();
    registry
        .insert(entry(
            "freestream-aero",
            Factory::Aero(Arc::new(|_| Ok(Box::new(FreestreamAero)))),
        ))
        .unwrap();
    registry
}

/// `[models.pod]` training a 6-mode basis into `basis_file` from the stand-in models: 1 s at
/// 0.1 s steps, 5 snapshots per run, at the Mach numbers `mach` (a TOML list body).
fn training_settings(basis_file: &str, mach: &str) -> toml::Table {
    toml::from_str(&format!(
        "basis_file = {basis_file:?}\nmodes = 6\n[training]\nheat_flux = \"relaxing-flux\"\n\
         aero = \"freestream-aero\"\nmach = [{mach}]\nduration_s = 1.0\n\
         dt_s = 0.1\nsnapshots_per_run = 5\n"
    ))
    .unwrap()
}

/// The registered `pod` built in the sample vehicle's region `region` with `settings`.
fn build_pod(
    registry: &Registry,
    region: &str,
    settings: &toml::Table,
) -> Result<Box<dyn ConductionModel>, hsv_core::registry::RegistryError> {
    let ctx = ModelContext {
        settings,
        key_path: "models.pod",
        file: "test.toml",
        region: hsv_core::testing::sample_region(region),
        registry,
    };
    registry.create::<dyn ConductionModel>("pod", &ctx)
}

/// The mirror surface takes the basis its twin trained (same fingerprint: the side is not part
/// of it) instead of training again, and saves it as its own; a sibling built from other
/// conditions is not taken. The right surface's own training gives the same basis to rounding
/// (its snapshots are the left's mirrored), which is why sharing it is sound.
#[test]
fn the_mirror_surface_reuses_its_twins_basis() {
    let dir = std::env::temp_dir().join(format!("hsv-pod-sibling-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let pattern = dir.join("basis-{region}.json").display().to_string();
    let settings = |mach: &str| training_settings(&pattern, mach);
    let registry = &training_registry();
    let build =
        |side: &str, table: &toml::Table| build_pod(registry, side, table).map(|m| m.cache());
    let left_file = dir.join("basis-left_surface.json");
    let right_file = dir.join("basis-right_surface.json");
    let first = settings("5.0, 6.0");
    build("left_surface", &first).expect("trains");
    let left = PodBasis::load(&left_file).expect("left saved");
    let taken = build("right_surface", &first).expect("takes the twin's");
    assert!(
        taken.is_some_and(|c| c.reused),
        "the right surface trained again"
    );
    assert_eq!(PodBasis::load(&right_file).expect("right saved"), left);

    // Its own training would have given the same modes to rounding.
    std::fs::remove_file(&left_file).unwrap();
    std::fs::remove_file(&right_file).unwrap();
    build("right_surface", &first).expect("trains");
    let own = PodBasis::load(&right_file).unwrap();
    assert_eq!(own.fingerprint, left.fingerprint);
    let largest = (&own.modes - &left.modes).amax();
    assert!(
        largest < 1e-9,
        "right's own basis differs from left's by {largest}"
    );

    // A sibling from other conditions is not taken: the left surface trains its own.
    let other = settings("6.5, 7.0");
    build("left_surface", &other).expect("trains");
    assert_ne!(
        PodBasis::load(&left_file).unwrap().fingerprint,
        own.fingerprint
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `pod` with a `[training]` table trains its basis when the file is missing, reuses it when
/// it was built from the same conditions, and retrains when anything it records changes.
#[test]
fn a_training_table_trains_reuses_and_retrains_the_basis() {
    let dir = std::env::temp_dir().join(format!("hsv-pod-training-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("basis.json");
    let basis_file = path.display().to_string();
    let settings = |mach: &str| training_settings(&basis_file, mach);
    let registry = &training_registry();
    let build = |table: &toml::Table| build_pod(registry, "right_surface", table);
    let first = settings("5.0, 6.0");
    let model = build(&first).expect("trains");
    assert_eq!(model.n_states(), 6);
    let saved = PodBasis::load(&path).expect("saved");
    assert!(!saved.fingerprint.is_empty());
    assert_eq!(
        saved.n_snapshots, 30,
        "5 snapshots from each of 6 runs: 2 Mach numbers at the default -4, 0, 4 deg"
    );
    assert_eq!(
        saved.training.as_ref().map(|t| t.mach.clone()),
        Some(vec![5.0, 6.0])
    );
    // Same conditions: the file is reused as it is.
    build(&first).expect("reuses");
    assert_eq!(PodBasis::load(&path).unwrap(), saved);
    // Other conditions: retrained and replaced.
    build(&settings("6.5, 7.0")).expect("retrains");
    let retrained = PodBasis::load(&path).unwrap();
    assert_ne!(retrained.fingerprint, saved.fingerprint);
    assert_eq!(retrained.training.map(|t| t.mach), Some(vec![6.5, 7.0]));
    // A bad training value names its key.
    let mut bad = settings("0.5");
    bad.insert("modes".into(), toml::Value::Integer(4));
    let err = build(&bad).err().expect("refused").to_string();
    assert!(err.contains("models.pod.training.mach[0]"), "{err}");
    // One angle as a number: one run per Mach number; an angle out of range names its index.
    let mut one_angle = settings("5.0, 6.0");
    let training = one_angle["training"].as_table().cloned().unwrap();
    let with_alpha = |alpha: toml::Value| {
        let mut t = training.clone();
        t.insert("alpha_deg".into(), alpha);
        t
    };
    one_angle.insert(
        "training".into(),
        toml::Value::Table(with_alpha(2.0.into())),
    );
    build(&one_angle).expect("trains at one angle");
    assert_eq!(PodBasis::load(&path).unwrap().n_snapshots, 10);
    let bad_angle = toml::Value::Array(vec![0.0.into(), 95.0.into()]);
    one_angle.insert("training".into(), toml::Value::Table(with_alpha(bad_angle)));
    let err = build(&one_angle).err().expect("refused").to_string();
    assert!(err.contains("models.pod.training.alpha_deg[1]"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 26 item 6: a saved basis whose numbers were edited (scaled) no longer matches its seal
/// and is refused as damaged, naming the file, instead of being used.
#[test]
fn an_edited_basis_file_is_refused_as_damaged() {
    let b = basis(4);
    let dir = std::env::temp_dir().join(format!("hsv-pod-edited-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("basis.json");
    b.save(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let first = b.singular_values[0];
    let edited = text.replacen(
        &serde_json::to_string(&first).unwrap(),
        &serde_json::to_string(&(2.0 * first)).unwrap(),
        1,
    );
    assert_ne!(edited, text);
    std::fs::write(&path, edited).unwrap();
    let error = PodBasis::load_cache(&path).unwrap_err();
    assert!(error.is_damaged(), "{error}");
    let message = PodBasis::load(&path).unwrap_err().to_string();
    assert!(
        message.contains("damaged") && message.contains("basis.json"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
