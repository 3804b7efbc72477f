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
