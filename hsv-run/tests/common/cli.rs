//! Running the `hsv-run` binary from the command-line tests: its output, text of each stream,
//! the JSON summary of a successful run, and a scratch folder per test crate and process.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `hsv-run args...`, in `dir` when given.
pub fn hsv_run_in(dir: Option<&Path>, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_hsv-run"));
    command.args(args);
    if let Some(dir) = dir {
        command.current_dir(dir);
    }
    command.output().expect("hsv-run starts")
}

/// `hsv-run args...` in the test's working folder.
pub fn hsv_run(args: &[&str]) -> Output {
    hsv_run_in(None, args)
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The stdout of `hsv-run args...`, which must succeed.
pub fn ok_stdout(args: &[&str]) -> String {
    let output = hsv_run(args);
    assert!(output.status.success(), "{args:?}: {}", stderr(&output));
    stdout(&output)
}

/// `hsv-run simulate` of `config` (the embedded sample when `None`) for `duration_s`, unheated,
/// quiet and without VTK frames, into `out`: the run must succeed; its stdout.
pub fn quiet_simulate(config: Option<&Path>, duration_s: &str, out: &Path) -> String {
    let mut args = vec!["simulate"];
    if let Some(config) = config {
        args.extend(["--config", config.to_str().expect("utf-8")]);
    }
    args.extend([
        "--duration-s",
        duration_s,
        "--no-heating",
        "--vtk-interval-s",
        "0",
    ]);
    args.extend(["--quiet", "--force", "--out", out.to_str().expect("utf-8")]);
    ok_stdout(&args)
}

/// The `--json` summary of a run that must have succeeded.
pub fn json(output: &Output) -> serde_json::Value {
    assert!(output.status.success(), "{}", stderr(output));
    serde_json::from_slice(&output.stdout).expect("valid JSON")
}

/// An empty folder `name` of this test crate and process under the system's temporary folder.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "hsv-{}-{}-{name}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}
