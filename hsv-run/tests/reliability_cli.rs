//! Issue 16 (reliability and everyday use): output never panics, run folders are unique and
//! say how the run ended, meshes are checked, config errors come early and name the key, and
//! plugins load from the named file.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use common::cli::{hsv_run, hsv_run_in, json, scratch_dir, stderr, stdout};

/// Expects failure with one `error:` line containing every needle and no panic.
fn expect_error(output: &Output, needles: &[&str]) -> String {
    let err = stderr(output);
    assert!(!output.status.success(), "succeeded: {}", stdout(output));
    assert!(!err.contains("panicked"), "panicked: {err}");
    assert!(err.starts_with("error:"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    for needle in needles {
        assert!(err.contains(needle), "`{needle}` not in: {err}");
    }
    err
}

// ---- 1. output never panics ----------------------------------------------------------------

#[test]
fn a_closed_stdout_pipe_ends_quietly_without_a_panic() {
    for args in [
        &["models"][..],
        &["config"],
        &["describe", "shock-expansion"],
        &["aero", "--all", "--json"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_hsv-run"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("hsv-run starts");
        // Close the reading end before the child writes (it builds its registry first).
        drop(child.stdout.take());
        let output = child.wait_with_output().expect("hsv-run ends");
        let err = stderr(&output);
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
        assert!(
            output.status.success() || output.status.code() == Some(141),
            "{args:?}: status {:?}: {err}",
            output.status
        );
        // Validity warnings (item 5) may precede the output; nothing else is said.
        assert!(
            err.lines().all(|l| l.starts_with("warning:")),
            "{args:?}: a closed pipe is not an error: {err}"
        );
    }
}

#[test]
fn a_full_disk_on_stdout_is_one_error_line() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        return; // not a Linux system
    };
    let output = Command::new(env!("CARGO_BIN_EXE_hsv-run"))
        .arg("models")
        .stdout(full)
        .output()
        .expect("hsv-run runs");
    expect_error(&output, &["standard output", "No space left"]);
}

// ---- 4. run folders ------------------------------------------------------------------------

#[test]
fn runs_started_together_get_their_own_folders() {
    let dir = scratch_dir("unique");
    let spawn = || {
        Command::new(env!("CARGO_BIN_EXE_hsv-run"))
            .args(["engine", "--json"])
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("hsv-run starts")
    };
    let children: Vec<_> = (0..3).map(|_| spawn()).collect();
    let mut folders: Vec<String> = children
        .into_iter()
        .map(|child| {
            let output = child.wait_with_output().expect("ends");
            json(&output)["run_folder"]
                .as_str()
                .expect("run folder")
                .to_owned()
        })
        .collect();
    folders.sort();
    folders.dedup();
    assert_eq!(folders.len(), 3, "shared run folders: {folders:?}");
    for folder in &folders {
        let summary: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(folder).join("summary.json")).expect("summary"),
        )
        .expect("JSON");
        assert_eq!(summary["status"]["state"], "completed");
    }
}

#[test]
fn out_refuses_a_non_empty_folder_unless_forced() {
    let dir = scratch_dir("force");
    std::fs::write(dir.join("keep.txt"), "mine").expect("write");
    let out = dir.to_str().expect("utf-8");
    let output = hsv_run(&["engine", "--out", out]);
    expect_error(&output, &["not empty", "--force"]);
    assert_eq!(
        std::fs::read_to_string(dir.join("keep.txt")).unwrap(),
        "mine"
    );
    let summary = json(&hsv_run(&["engine", "--json", "--out", out, "--force"]));
    assert_eq!(summary["status"]["state"], "completed");
    // Every file the JSON lists exists, and every file written is listed.
    let files: Vec<PathBuf> = summary["files"]
        .as_array()
        .expect("files")
        .iter()
        .map(|f| PathBuf::from(f.as_str().expect("path")))
        .collect();
    for name in [
        "thrust_vs_phi.csv",
        "thrust_vs_alpha.csv",
        "thrust_vs_phi_alpha.png",
        "summary.json",
    ] {
        assert!(files.contains(&dir.join(name)), "{name} not in {files:?}");
    }
    assert!(files.iter().all(|f| f.is_file()), "{files:?}");
}

#[test]
fn a_failed_run_says_why_in_its_summary_and_lists_what_it_wrote() {
    let dir = scratch_dir("failed");
    // A folder where the second CSV should go makes writing it fail.
    std::fs::create_dir_all(dir.join("thrust_vs_alpha.csv")).expect("blocker");
    let output = hsv_run(&["engine", "--out", dir.to_str().unwrap(), "--force"]);
    expect_error(&output, &["thrust_vs_alpha.csv"]);
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("summary.json")).expect("summary written"),
    )
    .expect("JSON");
    assert_eq!(summary["status"]["state"], "failed");
    let reason = summary["status"]["reason"].as_str().expect("reason");
    assert!(reason.contains("thrust_vs_alpha.csv"), "{reason}");
    let files = summary["files"].to_string();
    assert!(files.contains("thrust_vs_phi.csv"), "{files}");
    assert!(!files.contains("thrust_vs_alpha.csv"), "{files}");
    // No half-written file is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains("partial"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn every_command_json_lists_its_files_and_status() {
    let aero = json(&hsv_run(&["aero", "--json"]));
    assert_eq!(aero["files"], serde_json::json!([]));
    assert_eq!(aero["status"]["state"], "completed");
    let dir = scratch_dir("modes");
    let modes = json(&hsv_run(&[
        "modes",
        "--json",
        "--out",
        dir.join("run").to_str().unwrap(),
    ]));
    assert_eq!(modes["status"]["state"], "completed");
    let files = modes["files"].as_array().expect("files");
    assert!(files.len() > 2, "{files:?}");
    assert!(
        files
            .iter()
            .any(|f| f.as_str().unwrap().ends_with("summary.json"))
    );
    assert!(
        files
            .iter()
            .all(|f| Path::new(f.as_str().unwrap()).is_file())
    );
}

// ---- 6. meshes -----------------------------------------------------------------------------

/// The facets of the cube fixture: (normal, three vertices), as text tokens.
fn cube_facets() -> Vec<([f64; 3], [[f64; 3]; 3])> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../core/tests/data/cube_ascii.stl");
    let text = std::fs::read_to_string(path).expect("cube fixture");
    let numbers = |line: &str, skip: usize| -> [f64; 3] {
        let v: Vec<f64> = line
            .split_whitespace()
            .skip(skip)
            .map(|t| t.parse().expect("number"))
            .collect();
        [v[0], v[1], v[2]]
    };
    let mut facets = Vec::new();
    let mut normal = [0.0; 3];
    let mut vertices = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with("facet normal") {
            normal = numbers(line, 2);
            vertices.clear();
        } else if line.starts_with("vertex") {
            vertices.push(numbers(line, 1));
        } else if line.starts_with("endfacet") {
            facets.push((normal, [vertices[0], vertices[1], vertices[2]]));
        }
    }
    assert_eq!(facets.len(), 12);
    facets
}

fn write_stl(path: &Path, facets: &[([f64; 3], [[f64; 3]; 3])]) {
    let mut text = String::from("solid test\n");
    for (n, v) in facets {
        text += &format!("facet normal {} {} {}\nouter loop\n", n[0], n[1], n[2]);
        for p in v {
            text += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        text += "endloop\nendfacet\n";
    }
    text += "endsolid test\n";
    std::fs::write(path, text).expect("write STL");
}

/// A facet turned inside out: vertex order reversed and normal negated (the reader keeps it).
fn inside_out((n, [a, b, c]): ([f64; 3], [[f64; 3]; 3])) -> ([f64; 3], [[f64; 3]; 3]) {
    ([-n[0], -n[1], -n[2]], [a, c, b])
}

fn aero_json(mesh: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "aero",
        "--json",
        "--model",
        "newtonian-vector",
        "--alpha-deg",
        "10",
        "--mesh",
        mesh.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    hsv_run(&args)
}

fn force(summary: &serde_json::Value) -> Vec<f64> {
    summary["models"][0]["force_body_n"]
        .as_array()
        .expect("force")
        .iter()
        .map(|v| v.as_f64().expect("number"))
        .collect()
}

#[test]
fn an_inward_facing_mesh_is_turned_outward_with_a_warning() {
    let dir = scratch_dir("inward");
    let outward = dir.join("outward.stl");
    let inward = dir.join("inward.stl");
    write_stl(&outward, &cube_facets());
    write_stl(
        &inward,
        &cube_facets()
            .into_iter()
            .map(inside_out)
            .collect::<Vec<_>>(),
    );
    let reference = json(&aero_json(&outward, &[]));
    let output = aero_json(&inward, &[]);
    let turned = json(&output);
    assert!(
        stderr(&output).contains("warning:") && stderr(&output).contains("turned them outward"),
        "{}",
        stderr(&output)
    );
    assert!(turned["warnings"][0].as_str().unwrap().contains("outward"));
    let (a, b) = (force(&reference), force(&turned));
    assert!(a.iter().any(|f| f.abs() > 0.0));
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-9 * x.abs().max(1.0), "{a:?} vs {b:?}");
    }
}

#[test]
fn open_or_inconsistent_meshes_are_refused_unless_allowed() {
    let dir = scratch_dir("open");
    let open = dir.join("open.stl");
    write_stl(&open, &cube_facets()[1..]);
    expect_error(
        &aero_json(&open, &[]),
        &["open.stl", "open edges", "--allow-open"],
    );
    let output = aero_json(&open, &["--allow-open"]);
    assert!(
        json(&output)["warnings"][0]
            .as_str()
            .unwrap()
            .contains("--allow-open")
    );

    let mixed = dir.join("mixed.stl");
    let mut facets = cube_facets();
    facets[0] = inside_out(facets[0]);
    write_stl(&mixed, &facets);
    expect_error(
        &aero_json(&mixed, &[]),
        &["mixed.stl", "face opposite ways", "--allow-open"],
    );
}

#[test]
fn the_moment_point_is_an_option_and_moves_the_moment_as_r_cross_f() {
    let dir = scratch_dir("moment");
    let cube = dir.join("cube.stl");
    write_stl(&cube, &cube_facets());
    let centre = json(&aero_json(&cube, &[]));
    // Default for a mesh: the bounding-box centre.
    assert_eq!(centre["moment_point_m"], serde_json::json!([0.5, 0.5, 0.5]));
    let moved = json(&aero_json(&cube, &["--moment-point-m", "-2,1.5,0.25"]));
    assert_eq!(
        moved["moment_point_m"],
        serde_json::json!([-2.0, 1.5, 0.25])
    );
    // M_new = M_old + (r_old - r_new) × F.
    let f = force(&centre);
    let m = |s: &serde_json::Value| -> Vec<f64> {
        s["models"][0]["moment_body_nm"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    let (m0, m1) = (m(&centre), m(&moved));
    let d = [0.5 + 2.0, 0.5 - 1.5, 0.5 - 0.25];
    let cross = [
        d[1] * f[2] - d[2] * f[1],
        d[2] * f[0] - d[0] * f[2],
        d[0] * f[1] - d[1] * f[0],
    ];
    for k in 0..3 {
        let expected = m0[k] + cross[k];
        assert!(
            (m1[k] - expected).abs() <= 1e-9 * (expected.abs() + f[0].abs() + f[2].abs()),
            "component {k}: {} vs {expected}",
            m1[k]
        );
    }
    // A malformed point is a usage error from the argument parser.
    let output = hsv_run(&[
        "aero",
        "--mesh",
        cube.to_str().unwrap(),
        "--moment-point-m",
        "1,2",
    ]);
    assert!(!output.status.success());
    assert!(
        stderr(&output).contains("give three, X,Y,Z"),
        "{}",
        stderr(&output)
    );
}

// ---- 7. config errors ----------------------------------------------------------------------

fn sample_config(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let sample = stdout(&hsv_run(&["config"]));
    let edited = edit(sample.clone());
    assert_ne!(edited, sample, "edit did nothing");
    let path = dir.join("vehicle.toml");
    std::fs::write(&path, edited).expect("write config");
    path
}

#[test]
fn region_model_names_are_checked_before_any_command_runs() {
    let dir = scratch_dir("regions");
    let config = sample_config(&dir, |s| {
        s.replace(
            "[regions.propulsion]",
            "[regions.left_surface]\naero = \"shock-expanson\"\n\n[regions.propulsion]",
        )
    });
    let config = config.to_str().unwrap();
    // `modes` builds no aero model, yet the bad name is reported, with file and key path.
    for command in ["modes", "aero", "engine"] {
        expect_error(
            &hsv_run(&[command, "--config", config]),
            &[
                "vehicle.toml",
                "regions.left_surface.aero",
                "shock-expanson",
            ],
        );
    }
    let wrong_role = sample_config(&dir, |s| {
        s.replace(
            "[regions.propulsion]",
            "[regions.right_surface]\nstructure = \"eckert\"\n\n[regions.propulsion]",
        )
    });
    expect_error(
        &hsv_run(&["aero", "--config", wrong_role.to_str().unwrap()]),
        &["regions.right_surface.structure", "heat-flux model"],
    );
}

#[test]
fn a_non_finite_value_in_the_file_names_its_key() {
    let dir = scratch_dir("nan");
    let config = sample_config(&dir, |s| {
        let start = s.find("[flight]").expect("flight table");
        let line = s[start..].find("mach =").expect("mach") + start;
        let end = s[line..].find('\n').unwrap() + line;
        format!("{}mach = nan{}", &s[..line], &s[end..])
    });
    let err = expect_error(
        &hsv_run(&["aero", "--config", config.to_str().unwrap()]),
        &["vehicle.toml", "flight.mach", "finite"],
    );
    assert!(!err.contains("--mach"), "{err}");
}

#[test]
fn a_zero_reference_length_is_an_error_not_null_coefficients() {
    let dir = scratch_dir("lref");
    let config = sample_config(&dir, |s| {
        let start = s.find("[reference]").expect("reference table");
        let line = s[start..].find("chord_m =").expect("chord") + start;
        let end = s[line..].find('\n').unwrap() + line;
        format!("{}chord_m = 0.0{}", &s[..line], &s[end..])
    });
    expect_error(
        &hsv_run(&["aero", "--json", "--config", config.to_str().unwrap()]),
        &["reference.chord_m", "positive"],
    );
}

#[test]
fn config_check_says_ok_or_the_first_error() {
    let dir = scratch_dir("check");
    let good = sample_config(&dir, |s| s.replace("[flight]", "# checked\n[flight]"));
    let output = hsv_run(&["config", "--check", good.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(stdout(&output).trim(), format!("{}: OK", good.display()));
    let bad = sample_config(&dir, |s| s.replace("width_m =", "widht_m ="));
    expect_error(
        &hsv_run(&["config", "--check", bad.to_str().unwrap()]),
        &["vehicle.toml", "geometry.widht_m"],
    );
}

// ---- 8. plugins ----------------------------------------------------------------------------

#[test]
fn a_bare_plugin_name_is_the_file_here_not_a_system_library() {
    let dir = scratch_dir("plugin");
    std::fs::write(
        dir.join("junk.so"),
        "not a shared library, just text ".repeat(20),
    )
    .expect("write");
    // From the command line: the file in the current directory, with the loader's own words.
    let err = expect_error(
        &hsv_run_in(Some(&dir), &["--plugin", "junk.so", "models"]),
        &["junk.so", "cannot load the library"],
    );
    assert!(
        err.contains("invalid ELF header") || err.contains("too short"),
        "the loader's message is lost: {err}"
    );
    // A system library's bare name is not looked up on the library path.
    expect_error(
        &hsv_run_in(Some(&dir), &["--plugin", "libc.so.6", "models"]),
        &["libc.so.6", "cannot load the library", "No such file"],
    );
    // From a config: relative to the config's folder, whatever the current directory.
    let config = sample_config(&dir, |s| format!("plugins = [\"junk.so\"]\n{s}"));
    let elsewhere = scratch_dir("plugin-elsewhere");
    let err = expect_error(
        &hsv_run_in(
            Some(&elsewhere),
            &["aero", "--config", config.to_str().unwrap()],
        ),
        &["key `plugins`", "junk.so"],
    );
    assert!(
        err.contains("invalid ELF header") || err.contains("too short"),
        "{err}"
    );
}
