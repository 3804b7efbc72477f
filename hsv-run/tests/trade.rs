//! `hsv-run trade` and `hsv-run merge`: a two-combination rigid-trim study produces its table
//! (CSV, JSON, PNG) with the highest-fidelity combination as reference; N shards merged give the
//! same table as one unsharded run; the Slurm script names the array size and the commands.

use std::path::{Path, PathBuf};
use std::process::Command;

use hsv_core::config::LoadedConfig;
use hsv_run::analysis::trade::{
    CaseResult, Shard, StudySpec, TradeJob, compare, fingerprint, merge_cases, run_case,
};

const VARY: &str = "main_body.aero=newtonian-scalar,shock-expansion";

fn hsv_run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_hsv-run"))
        .args(args)
        .output()
        .expect("hsv-run starts")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hsv-trade-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The table without wall times (the only thing that differs between two runs of one study).
fn comparable(table: &serde_json::Value) -> serde_json::Value {
    let mut table = table.clone();
    for row in table["rows"].as_array_mut().unwrap() {
        row.as_object_mut().unwrap().remove("wall_time_s");
    }
    table
}

#[test]
fn two_aero_models_trim_study_produces_its_table() {
    let out = scratch("table");
    let run = hsv_run(&[
        "trade",
        "--vary",
        VARY,
        "--job",
        "trim",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        stdout.contains("main_body.aero=newtonian-scalar"),
        "{stdout}"
    );
    assert!(
        stdout.contains("main_body.aero=shock-expansion"),
        "{stdout}"
    );

    let table = json(&out.join("trade.json"));
    let rows = table["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    // shock-expansion has fidelity 3, newtonian-scalar 1: case 1 is the reference.
    assert_eq!(table["reference_case"], 1);
    assert_eq!(rows[1]["reference"], true);
    assert_eq!(rows[1]["error"].as_f64(), Some(0.0));
    let error = rows[0]["error"].as_f64().unwrap();
    assert!(error > 0.0 && error.is_finite(), "error {error}");
    for row in rows {
        assert!(row["failure"].is_null(), "{row}");
        assert!(row["wall_time_s"].as_f64().unwrap() > 0.0);
        let alpha = row["values"]["alpha_deg"].as_f64().unwrap();
        assert!(alpha.is_finite());
    }
    // The deviation of the cheap case is its own trim minus the reference's.
    let d = rows[0]["deviations"]["alpha_deg"].as_f64().unwrap();
    let a0 = rows[0]["values"]["alpha_deg"].as_f64().unwrap();
    let a1 = rows[1]["values"]["alpha_deg"].as_f64().unwrap();
    assert!((d - (a0 - a1).abs()).abs() < 1e-12);

    let csv = std::fs::read_to_string(out.join("trade.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(csv.starts_with(
        "case,combination,reference,pareto,fidelity_sum,wall_time_s,model_cost_s,error"
    ));
    let png = std::fs::read(out.join("trade.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let _ = std::fs::remove_dir_all(&out);
}

/// With model costs from a file, the whole table but the measured wall times is deterministic
/// (without one, the Pareto front is drawn on wall times, which vary from run to run).
#[test]
fn shards_merged_equal_one_unsharded_run() {
    let whole = scratch("whole");
    let costs = std::env::temp_dir().join(format!("hsv-trade-{}-costs.csv", std::process::id()));
    std::fs::write(
        &costs,
        "model,seconds\nnewtonian-scalar,2.5e-5\nshock-expansion,2.4e-4\n",
    )
    .unwrap();
    let costs = costs.to_str().unwrap();
    let run = hsv_run(&[
        "trade",
        "--vary",
        VARY,
        "--costs",
        costs,
        "--quiet",
        "--out",
        whole.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let mut shard_dirs = Vec::new();
    for k in 0..2 {
        let dir = scratch(&format!("shard-{k}"));
        let run = hsv_run(&[
            "trade",
            "--vary",
            VARY,
            "--quiet",
            "--shard",
            &format!("{k}/2"),
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        assert!(
            !dir.join("trade.csv").exists(),
            "a shard writes only its cases"
        );
        shard_dirs.push(dir);
    }
    let merged = scratch("merged");
    let mut args = vec!["merge".to_owned()];
    // Given in reverse: the order of the folders does not matter.
    args.extend(shard_dirs.iter().rev().map(|d| d.display().to_string()));
    args.extend([
        "--out".to_owned(),
        merged.display().to_string(),
        "--costs".to_owned(),
        costs.to_owned(),
    ]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = hsv_run(&args);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(
        comparable(&json(&merged.join("trade.json"))),
        comparable(&json(&whole.join("trade.json")))
    );

    // One shard alone is refused, naming the missing one.
    let run = hsv_run(&[
        "merge",
        shard_dirs[0].to_str().unwrap(),
        "--out",
        scratch("half").to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("1/2"), "{stderr}");
    let _ = std::fs::remove_file(costs);
    for dir in shard_dirs.iter().chain([&whole, &merged]) {
        let _ = std::fs::remove_dir_all(dir);
    }
    let _ = std::fs::remove_dir_all(scratch("half"));
}

/// Library level: the two shards of a study, given in reverse order, merge into exactly the
/// unsharded comparison (wall times included, since the same case results are reused).
#[test]
fn library_shards_merge_into_the_unsharded_comparison() {
    let loaded = LoadedConfig::sample().unwrap();
    let registry = hsv_run::registry().unwrap();
    let mut spec = StudySpec {
        job: TradeJob::Trim,
        variations: vec![VARY.parse().unwrap()],
        mach: loaded.config.flight.mach,
        altitude_m: loaded.config.flight.altitude_m,
        flight: None,
        flutter: None,
        config_file: loaded.file.clone(),
        config_fingerprint: fingerprint("sample"),
    };
    spec.rank(&registry).unwrap();
    let all: Vec<CaseResult> = (0..spec.case_count())
        .map(|i| run_case(&spec, &loaded, &registry, i))
        .collect();
    let whole = compare(&spec, all.clone(), None).unwrap();
    let parts = (0..2)
        .rev()
        .map(|k| {
            let shard = Shard { index: k, count: 2 };
            let cases = shard
                .cases(spec.case_count())
                .into_iter()
                .map(|i| all[i].clone())
                .collect();
            (
                format!("shard {k}"),
                hsv_run::analysis::trade::TradeCases {
                    spec: spec.clone(),
                    shard,
                    cases,
                },
            )
        })
        .collect();
    let (merged_spec, cases) = merge_cases(parts).unwrap();
    assert_eq!(merged_spec, spec);
    assert_eq!(compare(&spec, cases, None).unwrap(), whole);
}

#[test]
fn slurm_script_names_the_array_and_the_commands() {
    let out = scratch("slurm");
    let run = hsv_run(&[
        "trade",
        "--vary",
        VARY,
        "--vary",
        "propulsion.propulsion=scramjet-1d,scramjet-q1d",
        "--emit-slurm",
        "3",
        "--hsv-run",
        "/opt/hsv/bin/hsv-run",
        "--slurm-cpus",
        "16",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let array = std::fs::read_to_string(out.join("trade-array.sbatch")).unwrap();
    assert!(array.starts_with("#!/bin/bash\n"), "{array}");
    assert!(array.contains("#SBATCH --array=0-2\n"), "{array}");
    assert!(array.contains("#SBATCH --cpus-per-task=16\n"), "{array}");
    assert!(
        array.contains(
            "/opt/hsv/bin/hsv-run trade --job trim --vary main_body.aero=newtonian-scalar,shock-expansion \
             --vary propulsion.propulsion=scramjet-1d,scramjet-q1d"
        ),
        "{array}"
    );
    assert!(
        array.contains("--shard \"${SLURM_ARRAY_TASK_ID}/3\""),
        "{array}"
    );
    let submit = std::fs::read_to_string(out.join("submit.sh")).unwrap();
    assert!(
        submit.contains("array_job=$(sbatch --parsable trade-array.sbatch)"),
        "{submit}"
    );
    assert!(
        submit.contains("--dependency=afterok:${array_job}"),
        "{submit}"
    );
    assert!(
        submit
            .contains("'/opt/hsv/bin/hsv-run merge shard-0 shard-1 shard-2 --out merged --force'"),
        "{submit}"
    );
    // Nothing ran: no cases file.
    assert!(!out.join("trade-cases.json").exists());

    // More shards than cases is refused.
    let run = hsv_run(&[
        "trade",
        "--vary",
        VARY,
        "--emit-slurm",
        "5",
        "--out",
        scratch("slurm5").to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("only 2 cases"));
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(scratch("slurm5"));
}

#[test]
fn bad_variations_are_refused_before_any_case_runs() {
    let out = scratch("bad");
    let run = hsv_run(&[
        "trade",
        "--vary",
        "main_body.aero=newtonian-scalar,no-such-model",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("no-such-model"), "{stderr}");
    // A heat-flux model named as aero: wrong role.
    let run = hsv_run(&[
        "trade",
        "--vary",
        "main_body.aero=eckert",
        "--out",
        scratch("bad2").to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("eckert"));
    let run = hsv_run(&["trade", "--out", scratch("bad3").to_str().unwrap()]);
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("nothing to vary"));
    // A flutter study's grid given to a trim study.
    let run = hsv_run(&[
        "trade",
        "--vary",
        VARY,
        "--times-s",
        "0,10",
        "--out",
        scratch("bad4").to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    assert!(
        String::from_utf8_lossy(&run.stderr).contains("--times-s is an option of a flutter study")
    );
    for d in ["bad", "bad2", "bad3", "bad4"] {
        let _ = std::fs::remove_dir_all(scratch(d));
    }
}

#[test]
fn costs_file_sets_the_cost_column() {
    let out = scratch("costs");
    std::fs::create_dir_all(&out).unwrap();
    let costs = out.join("costs.csv");
    std::fs::write(
        &costs,
        "model,seconds,bench\nnewtonian-scalar,2.0e-4,aero/x\nshock-expansion,1.5e-3,aero/y\n",
    )
    .unwrap();
    let folder = out.join("run");
    let run = hsv_run(&[
        "trade",
        "--vary",
        VARY,
        "--costs",
        costs.to_str().unwrap(),
        "--quiet",
        "--json",
        "--out",
        folder.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let table = json(&folder.join("trade.json"));
    let cost = |i: usize| table["rows"][i]["model_cost_s"].as_f64().unwrap();
    assert_eq!((cost(0), cost(1)), (2.0e-4, 1.5e-3));
    // Cheaper and less accurate, dearer and exact: both on the front.
    assert_eq!(table["rows"][0]["pareto"], true);
    assert_eq!(table["rows"][1]["pareto"], true);

    // A model missing from the file is named.
    std::fs::write(&costs, "model,seconds\nnewtonian-scalar,2.0e-4\n").unwrap();
    let run = hsv_run(&[
        "trade",
        "--vary",
        VARY,
        "--costs",
        costs.to_str().unwrap(),
        "--quiet",
        "--out",
        out.join("run2").to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("shock-expansion"));
    let _ = std::fs::remove_dir_all(&out);
}

/// The sample config with `extra` TOML appended, written to a scratch folder named `name`.
fn sample_config_with(name: &str, extra: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::create_dir_all(&dir).unwrap();
    let sample = hsv_run(&["config"]);
    assert!(sample.status.success());
    let path = dir.join("config.toml");
    let text = format!("{}\n{extra}", String::from_utf8_lossy(&sample.stdout));
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs `hsv-run args`, which must succeed.
fn run_ok(args: &[&str]) {
    let run = hsv_run(args);
    assert!(
        run.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
}

/// The value of each of `channels` in the last row of a history CSV.
fn last_row(path: &Path, channels: &[&str]) -> Vec<f64> {
    let csv = std::fs::read_to_string(path).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let last: Vec<f64> = lines
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    channels
        .iter()
        .map(|c| last[header.iter().position(|h| h == c).unwrap()])
        .collect()
}

/// Equal to the ten significant digits history.csv prints.
fn assert_same_digits(channel: &str, a: f64, b: f64) {
    assert!(
        (a - b).abs() <= 1e-9 * b.abs().max(1e-3),
        "{channel}: {a} against {b}"
    );
}

const FINAL_CHANNELS: [&str; 5] = [
    "altitude_m",
    "airspeed_m_s",
    "alpha_deg",
    "pitch_deg",
    "q_deg_s",
];

/// Issue 25's defect: `trade --job simulate` flew its own setup (default integrator and body
/// rate, no heating), whatever `[simulation]` said. It now flies `simulate`'s, so a
/// one-combination study of the config's own models ends where `simulate` ends, to the digits
/// `history.csv` prints, on a config whose surfaces start hot (700 K) and soften every 5 ms (the
/// old setup, unheated, ended with α 2e-4 deg away).
#[test]
fn a_simulate_study_flies_what_simulate_flies() {
    let config = sample_config_with(
        "hot-surfaces",
        "[simulation]\ninitial_temperature_k = 700.0\nstiffness_interval_s = 0.005\n",
    );
    let dir = config.parent().unwrap();
    let (study, flown) = (dir.join("study"), dir.join("simulate"));
    let config = config.to_str().unwrap();
    let flight = [
        "--config",
        config,
        "--duration-s",
        "0.02",
        "--record-every",
        "1",
    ];
    let trade = [
        "trade",
        "--vary",
        "main_body.aero=shock-expansion-piston",
        "--job",
        "simulate",
        "--quiet",
        "--out",
        study.to_str().unwrap(),
    ];
    run_ok(&[&trade[..], &flight[..]].concat());
    let simulate = ["simulate", "--quiet", "--out", flown.to_str().unwrap()];
    run_ok(&[&simulate[..], &flight[..]].concat());

    let table = json(&study.join("trade.json"));
    let values = &table["rows"][0]["values"];
    let simulated = last_row(&flown.join("history.csv"), &FINAL_CHANNELS);
    for (channel, s) in FINAL_CHANNELS.iter().zip(simulated) {
        let studied = values[format!("final_{channel}")].as_f64().unwrap();
        assert_same_digits(channel, studied, s);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// `compare` flies its partitioned case through the same setup as `simulate --no-heating`: on a
/// config whose elevon steps 1 deg within the first 5 ms (`compare` used to fly the paper's
/// doublet whatever `[simulation.inputs]` said), both end on the same state, to history.csv's
/// ten digits.
#[test]
fn compare_flies_its_partitioned_case_as_simulate_does() {
    let config = sample_config_with(
        "early-step",
        "[simulation.inputs.symmetric_elevon_deg]\ntime_s = [0.0, 0.005]\nvalue = [0.0, 1.0]\n",
    );
    let dir = config.parent().unwrap();
    let (compared, flown) = (dir.join("compare"), dir.join("simulate"));
    let config = config.to_str().unwrap();
    let flight = ["--config", config, "--duration-s", "0.02"];
    run_ok(
        &[
            &["compare", "--out", compared.to_str().unwrap()][..],
            &flight[..],
        ]
        .concat(),
    );
    let simulate = [
        "simulate",
        "--quiet",
        "--no-heating",
        "--record-every",
        "10",
        "--out",
        flown.to_str().unwrap(),
    ];
    run_ok(&[&simulate[..], &flight[..]].concat());
    let channels = [
        "time_s",
        "altitude_m",
        "airspeed_m_s",
        "alpha_deg",
        "pitch_deg",
        "q_deg_s",
    ];
    let c = last_row(&compared.join("history_partitioned.csv"), &channels);
    let s = last_row(&flown.join("history.csv"), &channels);
    for ((channel, c), s) in channels.iter().zip(c).zip(s) {
        assert_same_digits(channel, c, s);
    }
    // Beside it the staggered scheme, sub-iterated (at least twice: the residual compares two)
    // to the sample's R_tol = 1e-5 m, a residual in metres at or below it.
    let staggered = last_row(
        &compared.join("history_partitioned_staggered.csv"),
        &["pitch_deg", "coupling_iterations", "coupling_residual"],
    );
    assert!(staggered[1] >= 2.0 && staggered[2] <= 1e-5, "{staggered:?}");
    let _ = std::fs::remove_dir_all(dir);
}
