//! `hsv-run linearize --grid` (issue 27 item 4), consistency checks rather than validation
//! (the linear model's physics is tested in `linearize.rs` above): each grid point holds the
//! model `linearize` gives at that point alone, a point that does not trim keeps its slot with its error, and
//! shards merged by `hsv-run merge` equal the unsharded grid. The `.npz` is read back by numpy
//! in the Python tests (`python/tests/test_commands.py`).

use crate::common::cli::{hsv_run, scratch_dir, stderr};

fn json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("file")).expect("JSON")
}

/// Runs `hsv-run args...` and fails the test with its stderr if it fails.
fn ok(args: &[&str]) {
    let output = hsv_run(args);
    assert!(output.status.success(), "{args:?}: {}", stderr(&output));
}

#[test]
fn grid_points_are_the_single_point_models_and_shards_merge_to_the_grid() {
    let dir = scratch_dir("grid");
    let config = dir.join("coarse.toml");
    std::fs::write(&config, crate::common::coarse_text()).unwrap();
    let config = config.to_str().unwrap();
    let path = |name: &str| dir.join(name).display().to_string();
    // Mach 6 at 25 and 26 km trims; 200 km is above the atmosphere model (86 km).
    let grid = ["--mach", "6", "--altitude-m", "25000,200000,26000"];
    let whole = path("whole");
    ok(&[
        &["linearize", "--config", config, "--grid", "--out", &whole][..],
        &grid,
    ]
    .concat());
    let cases = json(&dir.join("whole/linear-grid-cases.json"));
    let points = cases["cases"].as_array().expect("cases");
    assert_eq!(points.len(), 3);
    assert!(dir.join("whole/linear_models.npz").exists());
    // The point at 200 km has no model and says why; the others have one.
    assert!(points[1]["model"].is_null(), "{}", points[1]);
    assert!(
        points[1]["error"]
            .as_str()
            .is_some_and(|e| e.contains("outside the US Standard Atmosphere 1976")),
        "{}",
        points[1]
    );
    let summary = json(&dir.join("whole/summary.json"));
    assert_eq!(
        summary["failed"].as_array().map(Vec::len),
        Some(1),
        "{summary}"
    );

    // Point 2 (Mach 6, 26 km) against `linearize` at that point alone: the same numbers.
    let single = path("single");
    ok(&[
        "linearize",
        "--config",
        config,
        "--mach",
        "6",
        "--altitude-m",
        "26000",
        "--out",
        &single,
    ]);
    let alone = json(&dir.join("single/linear_model.json"));
    let point = &points[2]["model"];
    let nx = point["state_names"].as_array().expect("names").len();
    // nalgebra writes a matrix as [column-major data, rows, columns].
    let a_alone: Vec<f64> = alone["a"][0]
        .as_array()
        .map(|a| a.iter().filter_map(serde_json::Value::as_f64).collect())
        .expect("a");
    // The grid stores rows.
    let a_grid: Vec<f64> = point["a"]
        .as_array()
        .map(|a| a.iter().filter_map(serde_json::Value::as_f64).collect())
        .expect("a");
    assert_eq!(a_grid.len(), nx * nx);
    for i in 0..nx {
        for j in 0..nx {
            assert_eq!(a_grid[i * nx + j], a_alone[j * nx + i], "A[{i}][{j}]");
        }
    }

    // Two shards, merged, are the unsharded grid.
    let shards: Vec<String> = (0..2).map(|k| path(&format!("shard-{k}"))).collect();
    for (k, out) in shards.iter().enumerate() {
        let shard = format!("{k}/2");
        ok(&[
            &[
                "linearize",
                "--config",
                config,
                "--grid",
                "--shard",
                &shard,
                "--out",
                out,
            ][..],
            &grid,
        ]
        .concat());
        assert!(!dir.join(format!("shard-{k}/linear_models.npz")).exists());
    }
    let merged = path("merged");
    ok(&["merge", &shards[0], &shards[1], "--out", &merged]);
    assert_eq!(
        json(&dir.join("merged/linear-grid-cases.json"))["cases"],
        cases["cases"]
    );
    assert_eq!(
        std::fs::read(dir.join("merged/linear_models.npz")).unwrap(),
        std::fs::read(dir.join("whole/linear_models.npz")).unwrap()
    );
}

#[test]
fn grid_requests_are_checked_before_any_trim() {
    for (args, needle) in [
        (
            &["linearize", "--mach", "5,6"][..],
            "--mach and --altitude-m take one value each without --grid (got 2 and 1)",
        ),
        (
            &["linearize", "--grid", "--mach", "0.8"][..],
            "grid Mach numbers must be finite and above 1, got 0.8",
        ),
        (
            &["linearize", "--grid", "--altitude-m", "NaN"][..],
            "grid altitudes must be finite, got NaN",
        ),
        (&["linearize", "--shard", "0/2"][..], "--grid"),
        (
            &["linearize", "--grid", "--altitude-m", "200000"][..],
            "no point of the grid trims; the first error: no trim at Mach 6, 200000 m",
        ),
    ] {
        let output = hsv_run(args);
        let err = stderr(&output);
        assert!(!output.status.success(), "{args:?} succeeded");
        assert!(err.contains(needle), "{args:?}: `{needle}` not in {err}");
    }
}
