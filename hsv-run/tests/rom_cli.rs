//! `hsv-run rom identify|check`: the cache is written, reused and rebuilt as documented, the
//! check's outputs have the documented layout, and bad requests get one clear error line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn hsv_run(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hsv-run"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("hsv-run starts")
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hsv-rom-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn json(output: &Output) -> serde_json::Value {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).expect("JSON on stdout")
}

fn error_line(output: &Output) -> String {
    let err = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success());
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.starts_with("error:"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    err
}

/// The first `identify` writes the cache, the second reuses it, `--rebuild` identifies anew.
#[test]
fn identify_writes_reuses_and_rebuilds_the_cache() {
    let dir = scratch_dir("identify");
    let first = json(&hsv_run(&dir, &["rom", "identify", "--json"]));
    let rom = &first["rom"];
    assert_eq!(rom["from_cache"], false);
    assert_eq!(rom["source"], "shock-expansion-piston");
    assert_eq!(first["status"]["state"], "completed");
    let cache = dir.join("hsv-cache/convolution-rom-left_surface.json");
    assert!(cache.is_file(), "{}", cache.display());
    let second = json(&hsv_run(&dir, &["rom", "identify", "--json"]));
    assert_eq!(second["rom"]["from_cache"], true);
    let rebuilt = json(&hsv_run(&dir, &["rom", "identify", "--rebuild", "--json"]));
    assert_eq!(rebuilt["rom"]["from_cache"], false);
    // Another source is another identification.
    let piston = json(&hsv_run(
        &dir,
        &["rom", "identify", "--source", "piston-theory", "--json"],
    ));
    assert_eq!(piston["rom"]["from_cache"], false);
    assert_eq!(piston["rom"]["source"], "piston-theory");
}

/// `rom check`: one row of `rom-check-motions.csv` per mode plus the random motion, and
/// `rom-check.csv` with both histories of every step under the documented header.
#[test]
fn check_writes_both_histories_and_the_motion_table() {
    let dir = scratch_dir("check");
    let out = dir.join("run");
    let summary = json(&hsv_run(
        &dir,
        &[
            "rom",
            "check",
            "--region",
            "right_surface",
            "--forces-only",
            "--periods",
            "1",
            "--steps-per-period",
            "8",
            "--out",
            out.to_str().expect("utf-8"),
            "--json",
        ],
    ));
    let n = summary["rom"]["n_modes"].as_u64().expect("n_modes") as usize;
    let motions = summary["motions"].as_array().expect("motions");
    assert_eq!(motions.len(), n + 1);
    let steps: u64 = motions.iter().map(|m| m["steps"].as_u64().unwrap()).sum();
    let csv = std::fs::read_to_string(out.join("rom-check.csv")).expect("csv");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(header.len(), 2 + 2 * n);
    assert_eq!(
        &header[..3],
        &["motion", "time_s", "source_generalized_force_1_n_m"]
    );
    assert_eq!(header[2 + n], "rom_generalized_force_1_n_m");
    assert_eq!(lines.count() as u64, steps);
    let table = std::fs::read_to_string(out.join("rom-check-motions.csv")).expect("table");
    assert_eq!(table.lines().count(), n + 2);
    assert!(out.join("rom-check.png").is_file());
}

/// A model without the capability, an unknown source and an unknown region are refused.
#[test]
fn bad_requests_are_named() {
    let dir = scratch_dir("errors");
    let err = error_line(&hsv_run(
        &dir,
        &["rom", "identify", "--model", "piston-theory"],
    ));
    assert!(
        err.contains("`piston-theory`")
            && err.contains("reduced-order")
            && err.contains("`hsv-run rom`"),
        "{err}"
    );
    let err = error_line(&hsv_run(
        &dir,
        &["rom", "identify", "--source", "no-such-model"],
    ));
    assert!(err.contains("no-such-model"), "{err}");
    let err = error_line(&hsv_run(&dir, &["rom", "check", "--region", "tail"]));
    assert!(
        err.contains("tail") && err.contains("left_surface"),
        "{err}"
    );
}

/// Issue 26 item 6: a cache whose numbers were edited (seal broken), or whose arrays were cut
/// short and the seal recomputed, is rebuilt with a warning naming the file, never used or
/// panicked on (a cut-short cache used to panic `rom check` with an index out of range).
#[test]
fn an_edited_or_cut_short_cache_is_rebuilt_and_said_so() {
    let dir = scratch_dir("damaged");
    let first = json(&hsv_run(&dir, &["rom", "identify", "--json"]));
    assert_eq!(first["rom"]["from_cache"], false);
    let cache = dir.join("hsv-cache/convolution-rom-left_surface.json");
    let sealed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cache).unwrap()).unwrap();
    let write = |content: &serde_json::Value, reseal: bool| {
        let text = serde_json::to_string(content).unwrap();
        let checksum = if reseal {
            format!("{:016x}", hsv_core::cache::fnv1a(text.bytes()))
        } else {
            sealed["checksum"].as_str().unwrap().to_owned()
        };
        let bytes = if reseal {
            text.len()
        } else {
            sealed["bytes"].as_u64().unwrap() as usize
        };
        std::fs::write(
            &cache,
            format!(
                "{{\"seal\":\"hsv-cache-1\",\"checksum\":\"{checksum}\",\"bytes\":{bytes},\
                 \"content\":{text}}}"
            ),
        )
        .unwrap();
    };
    let mut scaled = sealed["content"].clone();
    for v in scaled["forces"]["steps"].as_array_mut().unwrap() {
        *v = serde_json::json!(2.0 * v.as_f64().unwrap());
    }
    let mut cut = sealed["content"].clone();
    cut["forces"]["steps"].as_array_mut().unwrap().truncate(3);
    for (what, content, reseal) in [("scaled", scaled, false), ("cut short", cut, true)] {
        write(&content, reseal);
        for command in [
            vec!["rom", "identify", "--json"],
            vec![
                "rom",
                "check",
                "--forces-only",
                "--periods",
                "1",
                "--steps-per-period",
                "8",
                "--out",
                "check",
                "--force",
                "--json",
            ],
        ] {
            let run = hsv_run(&dir, &command);
            let stderr = String::from_utf8_lossy(&run.stderr);
            assert!(!stderr.contains("panicked"), "{what}: {stderr}");
            let summary = json(&run);
            assert_eq!(summary["rom"]["from_cache"], false, "{what}: {summary}");
            assert!(
                stderr.contains("is damaged") && stderr.contains("rebuilding it"),
                "{what}: {stderr}"
            );
            assert!(
                stderr.contains("convolution-rom-left_surface.json"),
                "{stderr}"
            );
            // Damage it again for the next command (the rebuild wrote a good cache).
            write(&content, reseal);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
