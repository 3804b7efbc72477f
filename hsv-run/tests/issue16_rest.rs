//! Issue 16, the rest: `heat` on the shared output conventions (step rule, run folder with
//! `status` and `files`, inputs checked before the folder exists), caches in a named folder
//! that refuse a run outside what they hold (item 3), validity warnings and round-off clamping
//! (item 5), and plots and VTK files that say what they show (item 9).

mod common;

use std::path::{Path, PathBuf};

use common::cli::{hsv_run_in, json, scratch_dir, stderr};

use hsv_core::config::LoadedConfig;
use hsv_core::geometry::{Side, lifting_surface_mesh};
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::ConductionModel;
use hsv_model_conduction::{
    FullOrder, FullOrderSettings, Pod, PodBasis, PodSettings, collect_snapshots,
};

#[test]
fn refused_heat_inputs_leave_no_run_folder() {
    let dir = scratch_dir("refused");
    for args in [
        &["heat", "--model", "full-ordre"][..],
        &["heat", "--heat-flux", "eckrt"],
        &["heat", "--duration-s", "1e9", "--dt-s", "1e-3"],
        &[
            "heat",
            "--duration-s",
            "1",
            "--dt-s",
            "0.1",
            "--flux-interval-s",
            "0.15",
        ],
    ] {
        let output = hsv_run_in(Some(&dir), args);
        let err = stderr(&output);
        assert!(!output.status.success(), "{args:?} succeeded");
        assert!(!err.contains("panicked"), "{err}");
        assert!(err.starts_with("error:"), "{args:?}: {err}");
    }
    let err = stderr(&hsv_run_in(
        Some(&dir),
        &["heat", "--duration-s", "1e9", "--dt-s", "1e-3"],
    ));
    assert!(err.contains("1.000e12 steps"), "{err}");
    let err = stderr(&hsv_run_in(
        Some(&dir),
        &["heat", "--flux-interval-s", "0.15", "--dt-s", "0.1"],
    ));
    assert!(
        err.contains("--flux-interval-s") && err.contains("whole number"),
        "{err}"
    );
    assert!(
        !dir.join("runs").exists(),
        "a refused run created {:?}",
        std::fs::read_dir(dir.join("runs")).map(|d| d.count())
    );
}

#[test]
fn heat_ends_at_the_duration_and_its_json_has_status_and_files() {
    let dir = scratch_dir("heat-files");
    let out = dir.join("run");
    let out_str = out.to_str().expect("utf-8");
    // 0.25 s at 0.1 s: 0.1, 0.1 and 0.05 (rounding ran 0.3 s before).
    let summary = json(&hsv_run_in(
        None,
        &[
            "heat",
            "--model",
            "full-order",
            "--duration-s",
            "0.25",
            "--dt-s",
            "0.1",
            "--json",
            "--out",
            out_str,
        ],
    ));
    let model = &summary["models"][0];
    assert_eq!(model["steps"], 3);
    assert!(
        (model["final_time_s"].as_f64().expect("time") - 0.25).abs() < 1e-12,
        "{model}"
    );
    assert_eq!(summary["status"]["state"], "completed");
    let files: Vec<PathBuf> = summary["files"]
        .as_array()
        .expect("files")
        .iter()
        .map(|f| PathBuf::from(f.as_str().expect("path")))
        .collect();
    for name in [
        "temperature_history_full-order.csv",
        "temperature_range.png",
        "temperature_field_full-order.csv",
        "surface_full-order.pvd",
        "summary.json",
    ] {
        assert!(files.contains(&out.join(name)), "{name} not in {files:?}");
    }
    assert!(files.iter().all(|f| f.is_file()), "{files:?}");
    let written = std::fs::read_dir(&out).expect("folder").count();
    assert_eq!(written, files.len(), "files written but not listed");
    // The same folder again is refused without --force.
    let again = hsv_run_in(
        None,
        &[
            "heat",
            "--model",
            "full-order",
            "--duration-s",
            "0.2",
            "--out",
            out_str,
        ],
    );
    assert!(!again.status.success());
    assert!(stderr(&again).contains("--force"), "{}", stderr(&again));
    let _ = std::fs::remove_dir_all(&dir);
}

// ---- 3. caches that know what they hold ----------------------------------------------------

#[test]
fn the_pod_basis_is_cached_in_a_named_folder_and_its_location_printed() {
    let dir = scratch_dir("pod-cache");
    let output = hsv_run_in(
        Some(&dir),
        &[
            "heat",
            "--model",
            "pod",
            "--mach",
            "5",
            "--duration-s",
            "4",
            "--dt-s",
            "0.1",
            "--snapshot-mach",
            "4",
            "4.5",
            "5",
            "--json",
            "--out",
            "run",
        ],
    );
    let summary = json(&output);
    let basis = dir.join("hsv-cache").join("pod-basis-right_surface.json");
    assert!(basis.is_file(), "no basis at {}", basis.display());
    assert!(
        !dir.join("pod-basis.json").exists(),
        "basis left in the current directory"
    );
    let notes = summary["notes"].to_string();
    assert!(
        notes.contains("hsv-cache/pod-basis-right_surface.json"),
        "{notes}"
    );
    assert!(
        stderr(&output).contains("hsv-cache/pod-basis-right_surface.json"),
        "{}",
        stderr(&output)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

const SIGMA: f64 = 5.670_374_419e-8;

fn full_order() -> FullOrder {
    let cfg = LoadedConfig::sample()
        .expect("sample")
        .config
        .lifting_surface;
    let settings = FullOrderSettings::default();
    let grid = SurfaceGrid::lifting_surface(
        &cfg,
        Side::Right,
        settings.elements_chordwise,
        settings.elements_spanwise,
    )
    .expect("grid");
    let mesh = lifting_surface_mesh(&cfg, Side::Right).expect("mesh");
    FullOrder::new(&grid, &mesh, settings).expect("full order")
}

/// Uniform convection h (T_aw − T_w) less re-radiation on every panel.
fn convective(t_aw: f64, h: f64) -> impl FnMut(&[f64], &mut [f64]) {
    move |wall: &[f64], q: &mut [f64]| {
        for (q, w) in q.iter_mut().zip(wall) {
            *q = h * (t_aw - w) - 0.8 * SIGMA * w.powi(4);
        }
    }
}

/// A basis built from mild heating (walls below about 400 K) refuses a step that takes the
/// wall far beyond, naming the basis and the range, instead of extrapolating silently.
#[test]
fn a_pod_basis_refuses_a_run_hotter_than_its_snapshots() {
    let mut full = full_order();
    let mut mild = convective(420.0, 40.0);
    let snapshots = collect_snapshots(&mut full, 293.0, 1.0, 30, 1, |w, q| {
        mild(w, q);
        Ok(())
    })
    .expect("snapshots");
    let basis =
        PodBasis::from_snapshots(&snapshots, 6, FullOrderSettings::default()).expect("basis");
    let (lo, hi) = basis.temperature_range_k;
    assert!(hi < 430.0, "{lo}-{hi}");
    let settings = PodSettings {
        modes: 6,
        ..PodSettings::default()
    };
    let mut pod = Pod::new(&full, basis, settings)
        .expect("pod")
        .with_basis_file("mild-basis.json");
    let mut state = pod.uniform_state(293.0).expect("state");
    let n = pod.n_surface_panels();
    let (mut wall, mut q) = (vec![0.0; n], vec![0.0; n]);
    let mut hot = convective(2000.0, 400.0);
    let mut refused = None;
    for _ in 0..200 {
        pod.surface_temperatures(&state, &mut wall);
        hot(&wall, &mut q);
        if let Err(e) = pod.step(&mut state, &q, 1.0) {
            refused = Some(e.to_string());
            break;
        }
    }
    let message = refused.expect("the hot run was refused");
    assert!(
        message.contains("mild-basis.json") && message.contains("range"),
        "{message}"
    );
}

// ---- 5. validity warnings, round-off clamping --------------------------------------------

#[test]
fn a_point_outside_a_models_range_is_warned_on_stderr_and_in_the_json() {
    let output = hsv_run_in(
        None,
        &[
            "aero",
            "--model",
            "newtonian-vector",
            "--mach",
            "3",
            "--json",
        ],
    );
    let summary = json(&output);
    assert!(
        stderr(&output).contains("warning: newtonian-vector: Mach 3"),
        "{}",
        stderr(&output)
    );
    let warnings = summary["warnings"].to_string();
    assert!(warnings.contains("hypersonic"), "{warnings}");
    // At Mach 8 Newtonian theory is in its range: no Mach warning.
    let output = hsv_run_in(
        None,
        &[
            "aero",
            "--model",
            "newtonian-vector",
            "--mach",
            "8",
            "--json",
        ],
    );
    assert!(!stderr(&output).contains("Mach 8"), "{}", stderr(&output));

    let dir = scratch_dir("phi");
    let output = hsv_run_in(
        None,
        &[
            "engine",
            "--phi",
            "1.4",
            "--json",
            "--out",
            dir.join("run").to_str().unwrap(),
        ],
    );
    let summary = json(&output);
    assert!(
        stderr(&output).contains("stoichiometric"),
        "{}",
        stderr(&output)
    );
    assert!(summary["warnings"].to_string().contains("stoichiometric"));
}

/// A wall a micro-kelvin below the material table's 293 K floor is round-off: both conduction
/// models take it; a wall 30 K below is still refused with the range.
#[test]
fn round_off_below_the_table_floor_is_clamped_in_every_conduction_model() {
    let mut full = full_order();
    let cold = 293.0 - 1e-6;
    let mut state = full
        .uniform_state(cold)
        .expect("full-order takes round-off");
    let q = vec![0.0; full.n_surface_panels()];
    full.step(&mut state, &q, 0.1).expect("full-order steps");
    assert!(full.uniform_state(263.0).is_err());

    // POD from a small basis: property lines fitted from a range starting below the floor.
    let mut mild = convective(400.0, 30.0);
    let mut snapshots = collect_snapshots(&mut full, 293.0, 1.0, 12, 1, |w, q| {
        mild(w, q);
        Ok(())
    })
    .expect("snapshots");
    // Shift the coolest snapshot temperature to a micro-kelvin below the floor.
    let coolest = snapshots
        .iter()
        .map(|s| s.min())
        .fold(f64::INFINITY, f64::min);
    for s in &mut snapshots {
        s.add_scalar_mut(293.0 - 1e-6 - coolest);
    }
    let basis =
        PodBasis::from_snapshots(&snapshots, 4, FullOrderSettings::default()).expect("basis");
    assert!(basis.temperature_range_k.0 < 293.0);
    let pod = Pod::new(
        &full,
        basis,
        PodSettings {
            modes: 4,
            ..PodSettings::default()
        },
    );
    assert!(pod.is_ok(), "{:?}", pod.err());
}

// ---- 9. plots and VTK files that say what they show ----------------------------------------

fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).expect("png");
    let word =
        |at: usize| u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    (word(16), word(20))
}

#[test]
fn every_surface_mode_is_mapped_and_mode_vtk_files_record_mode_frequency_and_scale() {
    let dir = scratch_dir("modes");
    let out = dir.join("run");
    let summary = json(&hsv_run_in(
        None,
        &["modes", "--json", "--out", out.to_str().unwrap()],
    ));
    let modes = summary["surfaces"]["right"]
        .as_array()
        .expect("modes")
        .len();
    assert!(modes > 6, "{modes}");
    // One contour map per mode, four to a row (before: six line plots, three to a row).
    let (width, height) = png_size(&out.join("surface-modes.png"));
    assert_eq!(width, 4 * 440);
    assert_eq!(height, 520 * modes.div_ceil(4) as u32);
    let vtk = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("right-surface-mode-01"))
        })
        .expect("mode 1 VTK");
    let text = std::fs::read_to_string(vtk).unwrap();
    let header: Vec<&str> = text.lines().take(12).collect();
    assert!(
        header[1].contains("mode 1") && header[1].contains("Hz"),
        "{header:?}"
    );
    assert!(header[1].contains("displaced by"), "{header:?}");
    for field in ["mode_number", "frequency_hz", "display_scale"] {
        assert!(
            header.iter().any(|l| l.starts_with(field)),
            "{field} not in {header:?}"
        );
    }
    let f1 = summary["surfaces"]["right"][0]["frequency_hz"]
        .as_f64()
        .unwrap();
    let recorded: f64 = header
        .iter()
        .position(|l| l.starts_with("frequency_hz"))
        .map(|i| header[i + 1].parse().unwrap())
        .unwrap();
    assert!((recorded - f1).abs() <= 1e-9 * f1, "{recorded} vs {f1}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn models_get_distinct_line_styles() {
    use hsv_run::output::{LinePlot, Series, default_styles};
    let line = |label: &str| Series {
        label: label.into(),
        x: vec![0.0, 1.0],
        y: vec![0.0, 1.0],
    };
    let plot = LinePlot {
        title: String::new(),
        x_label: String::new(),
        y_label: String::new(),
        series: ["full-order max", "full-order min", "pod max", "pod min"]
            .into_iter()
            .map(line)
            .collect(),
    };
    let styles = default_styles(&plot);
    // Same statistic, same colour; different model, different dash.
    assert_eq!(styles[0].colour, styles[2].colour);
    assert_ne!(styles[0].dash, styles[2].dash);
    assert_ne!(styles[0].colour, styles[1].colour);
    let single = LinePlot {
        series: ["scramjet-1d", "scramjet-q1d"]
            .into_iter()
            .map(line)
            .collect(),
        ..plot
    };
    let styles = default_styles(&single);
    assert!(styles[0].colour != styles[1].colour && styles[0].dash != styles[1].dash);
}
