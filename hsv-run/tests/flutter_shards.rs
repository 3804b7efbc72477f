//! Flutter past one machine and in trade studies: `hsv-run flutter --shard K/N` shards merged by
//! `hsv-run merge` give the unsharded run's tables byte for byte; `--emit-slurm` writes the
//! array and the merge; `hsv-run trade --job flutter` tabulates each combination's flutter
//! Mach number against the highest-fidelity one; and the left surface, the right one's mirror
//! image, has the right one's stability.

use std::path::{Path, PathBuf};
use std::process::Command;

use hsv_core::config::LoadedConfig;
use hsv_run::analysis::flutter::sweep::{FlutterModels, FlutterSetup, flutter_point};
use hsv_run::analysis::flutter::{DerivativeMethod, SurfaceOptions};
use hsv_run::analysis::heating::HeatingSteps;

/// A coarse grid that brackets the cold surface's flutter crossing (Mach 2 stable; the sample
/// surface's thickness is calibrated to flutter cold near the paper's Mach 16.1 with
/// `shock-expansion-piston`), with one heated time: cheap in a debug build (seconds).
const GRID: [&str; 9] = [
    "--mach-range",
    "2:40",
    "--mach-step",
    "19",
    "--times-s",
    "0,1",
    "--dt-s",
    "0.5",
    "--no-compare",
];

/// The tables a flutter run writes (wall times are only in summary.json).
const TABLES: [&str; 4] = [
    "flutter_mach.csv",
    "divergence_mach.csv",
    "root_loci.csv",
    "temperature_range.csv",
];

fn hsv_run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_hsv-run"))
        .args(args)
        .output()
        .expect("hsv-run starts")
}

fn succeed(args: &[&str]) -> String {
    let run = hsv_run(args);
    assert!(
        run.status.success(),
        "hsv-run {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&run.stderr)
    );
    String::from_utf8_lossy(&run.stdout).into_owned()
}

fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("hsv-flutter-shards-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn flutter(extra: &[&str], out: &Path) -> String {
    let mut args = vec!["flutter"];
    args.extend(GRID);
    args.extend(extra);
    args.extend(["--out", out.to_str().unwrap()]);
    succeed(&args)
}

/// root_loci.csv as rows of (column name -> value).
fn root_loci(dir: &Path) -> Vec<std::collections::HashMap<String, f64>> {
    let text = std::fs::read_to_string(dir.join("root_loci.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(|v| v.parse::<f64>().unwrap()))
                .collect()
        })
        .collect()
}

/// The cold boundary is a flutter crossing (an oscillatory pair: nonzero frequency, with the
/// mode it grows from), reported apart from divergence; root_loci.csv holds every point the
/// boundary search evaluated, each with exactly one critical root, the largest real part of
/// its roots, and the crossing's frequency is that of the critical oscillatory root at the
/// unstable end of the final bracket. Bookkeeping of the outputs, not physics.
#[test]
fn flutter_is_reported_apart_from_divergence_with_every_searched_root() {
    let out = scratch("loci");
    flutter(&[], &out);
    let summary = json(&out.join("summary.json"));
    let cold = &summary["boundaries"][0];
    let flutter = &cold["flutter"];
    assert_eq!(flutter["kind"], "crossing", "{cold}");
    let frequency = flutter["frequency_hz"].as_f64().unwrap();
    assert!(frequency > 0.0, "flutter is an oscillatory pair: {flutter}");
    assert!(
        flutter["grows_from"]["mode"].as_u64().is_some(),
        "{flutter}"
    );
    assert!(cold.get("divergence").is_some(), "{cold}");
    let evaluations = flutter["evaluations"].as_u64().unwrap() as usize;
    let rows = root_loci(&out);
    let searched: Vec<_> = rows
        .iter()
        .filter(|r| r["time_s"] == 0.0 && r["search"] == 1.0)
        .collect();
    let mut machs: Vec<f64> = searched.iter().map(|r| r["mach"]).collect();
    machs.dedup();
    assert_eq!(
        machs.len(),
        evaluations,
        "one block of roots per evaluation"
    );
    for &mach in &machs {
        let point: Vec<_> = searched.iter().filter(|r| r["mach"] == mach).collect();
        let critical: Vec<_> = point.iter().filter(|r| r["critical"] == 1.0).collect();
        assert_eq!(critical.len(), 1, "Mach {mach}");
        let largest = point
            .iter()
            .map(|r| r["real_per_s"])
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(critical[0]["real_per_s"], largest, "Mach {mach}");
    }
    // The CSV's numbers are printed to fewer digits than the summary's.
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs().max(1.0);
    let bracket = flutter["bracket"].as_array().unwrap();
    let ends: Vec<f64> = bracket.iter().map(|v| v.as_f64().unwrap()).collect();
    assert!(
        ends.iter()
            .all(|e| rows.iter().any(|r| near(r["mach"], *e))),
        "the final bracket's ends are evaluated points: {ends:?}"
    );
    let at_frequency = rows
        .iter()
        .any(|r| r["time_s"] == 0.0 && r["imag_rad_s"] > 0.0 && near(r["frequency_hz"], frequency));
    assert!(
        at_frequency,
        "the crossing root {frequency} Hz is in root_loci.csv"
    );
}

#[test]
fn flutter_shards_merged_equal_one_unsharded_run() {
    let whole = scratch("whole");
    flutter(&[], &whole);
    let shards: Vec<PathBuf> = (0..2)
        .map(|k| {
            let dir = scratch(&format!("shard-{k}"));
            flutter(&["--shard", &format!("{k}/2")], &dir);
            assert!(
                !dir.join("flutter_mach.csv").exists(),
                "a shard writes only its columns"
            );
            dir
        })
        .collect();
    let merged = scratch("merged");
    // Given in reverse: the order of the folders does not matter.
    succeed(&[
        "merge",
        shards[1].to_str().unwrap(),
        shards[0].to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    for table in TABLES {
        assert_eq!(
            std::fs::read(merged.join(table)).unwrap(),
            std::fs::read(whole.join(table)).unwrap(),
            "{table} differs between the merged shards and the unsharded run"
        );
    }
    let (m, w) = (
        json(&merged.join("summary.json")),
        json(&whole.join("summary.json")),
    );
    assert_eq!(m["boundaries"], w["boundaries"]);
    assert_eq!(m["mach_grid"], w["mach_grid"]);
    // The grid brackets a crossing, so the merge ran the root finding on the merged grid.
    assert!(
        w["boundaries"][0]["flutter_mach"].as_f64().is_some(),
        "{}",
        w["boundaries"]
    );

    // One shard alone is refused, naming the missing one; so is a shard of another grid.
    let half = scratch("half");
    let run = hsv_run(&[
        "merge",
        shards[0].to_str().unwrap(),
        "--out",
        half.to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("1/2"));
    let other = scratch("other");
    succeed(&[
        "flutter",
        "--mach-range",
        "2:40",
        "--mach-step",
        "38",
        "--times-s",
        "0",
        "--no-compare",
        "--shard",
        "1/2",
        "--out",
        other.to_str().unwrap(),
    ]);
    let run = hsv_run(&[
        "merge",
        shards[0].to_str().unwrap(),
        other.to_str().unwrap(),
        "--out",
        half.to_str().unwrap(),
        "--force",
    ]);
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("different flutter map"));
    for dir in shards.iter().chain([&whole, &merged, &half, &other]) {
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// The merge reruns the root finding on the config the shards ran on: a config edited since is
/// refused, naming the file.
#[test]
fn a_config_changed_after_the_shards_is_refused() {
    let dir = scratch("config");
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("vehicle.toml");
    std::fs::write(&config, succeed(&["config"])).unwrap();
    let shard = |k: usize| {
        let out = dir.join(format!("shard-{k}"));
        succeed(&[
            "flutter",
            "--config",
            config.to_str().unwrap(),
            "--mach-range",
            "2:40",
            "--mach-step",
            "38",
            "--times-s",
            "0",
            "--no-compare",
            "--shard",
            &format!("{k}/2"),
            "--out",
            out.to_str().unwrap(),
        ]);
        out
    };
    let (s0, s1) = (shard(0), shard(1));
    // A comment alone leaves the parsed config, and so its fingerprint, as it was.
    let text = std::fs::read_to_string(&config).unwrap();
    assert!(
        text.contains("emissivity = 0.8 "),
        "the sample's eckert emissivity"
    );
    let text = text.replacen("emissivity = 0.8 ", "emissivity = 0.5 ", 1);
    std::fs::write(&config, text).unwrap();
    let run = hsv_run(&[
        "merge",
        s0.to_str().unwrap(),
        s1.to_str().unwrap(),
        "--out",
        dir.join("merged").to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("has changed since the flutter shards ran")
            && stderr.contains("vehicle.toml"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn flutter_slurm_script_runs_the_shards_and_the_merge() {
    let out = scratch("slurm");
    let mut args = vec!["flutter"];
    args.extend(GRID);
    args.extend([
        "--emit-slurm",
        "3",
        "--hsv-run",
        "/opt/hsv/bin/hsv-run",
        "--slurm-cpus",
        "4",
        "--out",
        out.to_str().unwrap(),
    ]);
    succeed(&args);
    let array = std::fs::read_to_string(out.join("flutter-array.sbatch")).unwrap();
    assert!(array.contains("#SBATCH --array=0-2\n"), "{array}");
    assert!(array.contains("#SBATCH --cpus-per-task=4\n"), "{array}");
    assert!(
        array.contains(
            "/opt/hsv/bin/hsv-run flutter --altitude-m 10000 --mach-range 2:40 --mach-step 19 \
             --times-s=0,1"
        ),
        "{array}"
    );
    assert!(
        array.contains("--shard \"${SLURM_ARRAY_TASK_ID}/3\""),
        "{array}"
    );
    let submit = std::fs::read_to_string(out.join("submit.sh")).unwrap();
    assert!(
        submit.contains("array_job=$(sbatch --parsable flutter-array.sbatch)"),
        "{submit}"
    );
    // The merge runs the root finding: a shard's CPUs, not one.
    assert!(submit.contains("--cpus-per-task=4"), "{submit}");
    assert!(
        submit
            .contains("'/opt/hsv/bin/hsv-run merge shard-0 shard-1 shard-2 --out merged --force'"),
        "{submit}"
    );
    assert!(!out.join("flutter-cases.json").exists(), "nothing ran");
    let _ = std::fs::remove_dir_all(&out);
}

/// Two aero models on the left surface: each row holds the flutter Mach number where the
/// surface flutters in the range, else says so with its largest real part and least damping;
/// the error of a row is |M_f − M_f,ref| / M_f,ref of its and the reference's values.
#[test]
fn flutter_trade_of_two_aero_models_produces_its_table() {
    let out = scratch("trade");
    let stdout = succeed(&[
        "trade",
        "--job",
        "flutter",
        "--vary",
        "left_surface.aero=piston-theory,shock-expansion-piston",
        "--mach-range",
        "2:40",
        "--mach-step",
        "19",
        "--times-s",
        "0",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(stdout.contains("flutter at left_surface"), "{stdout}");
    let table = json(&out.join("trade.json"));
    let rows = table["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    // shock-expansion-piston has fidelity 4, piston-theory 2.
    assert_eq!(table["reference_case"], 1);
    assert_eq!(rows[1]["error"].as_f64(), Some(0.0));
    let key = "flutter_mach_at_0_s";
    let mach = |i: usize| rows[i]["values"][key].as_f64();
    for (i, row) in rows.iter().enumerate() {
        assert!(row["failure"].is_null(), "{row}");
        let boundary = &row["flutter_boundaries"][0];
        assert_eq!(boundary["time_s"], 0.0);
        match mach(i) {
            Some(m) => {
                assert_eq!(boundary["boundary"]["kind"], "crossing", "{row}");
                assert!((2.0..=40.0).contains(&m), "{m}");
            }
            None => {
                assert!(row["values"]["least_damping_ratio_at_0_s"].is_number());
                assert!(row["values"]["max_real_per_s_at_0_s"].is_number());
            }
        }
    }
    match (mach(0), mach(1)) {
        (Some(m), Some(r)) => {
            let e = rows[0]["error"].as_f64().unwrap();
            assert!((e - (m - r).abs() / r).abs() < 1e-12, "{e} {m} {r}");
            let d = rows[0]["deviations"][key].as_f64().unwrap();
            assert!((d - (m - r).abs()).abs() < 1e-12);
        }
        (None, None) => assert_eq!(rows[0]["error"].as_f64(), Some(0.0)),
        _ => assert!(rows[0]["error"].is_null()),
    }
    let csv = std::fs::read_to_string(out.join("trade.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.contains(",flutter_boundaries,failure"), "{header}");
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert_eq!(&std::fs::read(out.join("trade.png")).unwrap()[1..4], b"PNG");
    let _ = std::fs::remove_dir_all(&out);
}

/// The vehicle is symmetric in y, so the left surface heated in the flow has the right one's
/// roots (mirror symmetry; to 1e-9 of the largest real part, round-off of the mirrored mesh).
#[test]
fn the_left_surface_is_the_right_ones_mirror_image() {
    let loaded = LoadedConfig::sample().unwrap();
    let registry = hsv_run::registry().unwrap();
    let setup = |region: &str| FlutterSetup {
        region: loaded.region(region).unwrap(),
        models: FlutterModels {
            aero: "shock-expansion-piston".into(),
            heat_flux: "eckert".into(),
            conduction: "full-order".into(),
            structure: "ritz-plate".into(),
        },
        altitude_m: 10_000.0,
        alpha_rad: 0.0,
        heating: HeatingSteps {
            dt_s: 0.5,
            flux_every: 1,
            initial_k: 293.0,
        },
        method: DerivativeMethod::Direct,
        compare_methods: false,
        options: SurfaceOptions::default(),
    };
    let point = |region: &str| flutter_point(&setup(region), &registry, 6.0, 1.0).unwrap();
    let (left, right) = (point("left_surface"), point("right_surface"));
    let (l, r) = (left.max_real_per_s.unwrap(), right.max_real_per_s.unwrap());
    assert!((l - r).abs() <= 1e-9 * r.abs().max(1.0), "{l} vs {r}");
    assert!(
        (left.max_temperature_k - right.max_temperature_k).abs() < 1e-9 * right.max_temperature_k
    );
    assert!(left.max_temperature_k > 293.0, "the surface heated");
}
