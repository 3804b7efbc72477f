//! Run outputs: standard output, run folders, CSV time histories, PNG line plots and VTK meshes
//! for ParaView.
//!
//! Every command that writes files goes through here, so all runs look alike: one folder per run
//! (`runs/<command>-<UTC time>-<ms>/` unless `--out` names one), CSV with units in the headers,
//! PNG plots of what the paper plots, legacy-VTK meshes plus a `.pvd` collection to animate them,
//! and a `summary.json` with the run's `status` and the `files` it wrote. Files are written
//! whole or not at all (a temporary file renamed into place), so a full disk never leaves a
//! truncated file behind. Text for the user goes through [`outln!`](crate::outln), which turns a
//! closed pipe or a full disk into an error instead of a panic.

use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use anyhow::{Context, Result, bail};
use hsv_core::mesh::PanelMesh;
use nalgebra::Vector3;
use plotters::prelude::*;

mod plot;
mod vtk;

pub use plot::*;
pub use vtk::*;

/// Standard output went away (the reader closed the pipe, as `hsv-run models | head -1` does):
/// not a failure of the run, so `main` exits quietly.
#[derive(Debug, thiserror::Error)]
#[error("standard output was closed")]
pub struct StdoutClosed;

/// Writes formatted text to standard output: a closed pipe is [`StdoutClosed`], any other
/// failure (a full disk) an error naming standard output. Use [`outln!`](crate::outln).
pub fn write_stdout(text: std::fmt::Arguments<'_>) -> Result<()> {
    std::io::stdout()
        .lock()
        .write_fmt(text)
        .map_err(stdout_error)
}

/// Flushes standard output (what a `print!` without a newline left in the buffer).
pub fn flush_stdout() -> Result<()> {
    std::io::stdout().lock().flush().map_err(stdout_error)
}

fn stdout_error(error: std::io::Error) -> anyhow::Error {
    if error.kind() == std::io::ErrorKind::BrokenPipe {
        StdoutClosed.into()
    } else {
        anyhow::anyhow!("cannot write to standard output: {error}")
    }
}

/// `println!` that returns `Result` instead of panicking when standard output fails.
#[macro_export]
macro_rules! outln {
    () => {
        $crate::output::write_stdout(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::output::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that returns `Result` instead of panicking when standard output fails.
#[macro_export]
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::output::write_stdout(format_args!($($arg)*))
    };
}

/// Writes `bytes` to `path` whole or not at all: into a temporary file beside it, renamed into
/// place when complete, so a failure (a full disk) leaves no truncated file.
pub fn write_file(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    let partial = partial_path(path);
    let written = fs::write(&partial, bytes).and_then(|()| fs::rename(&partial, path));
    if let Err(error) = written {
        let _ = fs::remove_file(&partial);
        bail!("cannot write {}: {error}", path.display());
    }
    Ok(())
}

/// An uncompressed zip archive of `members` (name, bytes) in memory, in their order: the
/// container of `.npz` files and FMUs.
pub fn zip_archive(members: &[(String, Vec<u8>)]) -> Result<Vec<u8>> {
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .large_file(
            members
                .iter()
                .any(|(_, bytes)| bytes.len() >= u32::MAX as usize),
        );
    for (name, bytes) in members {
        zip.start_file(name.as_str(), options)
            .with_context(|| format!("zip member {name}"))?;
        zip.write_all(bytes)
            .with_context(|| format!("zip member {name}"))?;
    }
    Ok(zip
        .finish()
        .context("finishing the zip archive")?
        .into_inner())
}

/// `.name.partial.ext` beside `path` (the extension kept: the PNG writer goes by it).
fn partial_path(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let name = match path.extension() {
        Some(ext) => format!(".{stem}.partial.{}", ext.to_string_lossy()),
        None => format!(".{stem}.partial"),
    };
    path.with_file_name(name)
}

/// Creates the run folder: `out` if given (refused when it holds files, unless `force`), else a
/// new `runs/<command>-<UTC time>-<milliseconds>` (with `-2`, `-3`, ... when runs start in the
/// same millisecond).
pub fn create_run_folder(command: &str, out: Option<&Path>, force: bool) -> Result<PathBuf> {
    match out {
        Some(folder) => {
            let has_files = fs::read_dir(folder).is_ok_and(|mut entries| entries.next().is_some());
            if has_files && !force {
                bail!(
                    "the run folder {} is not empty; choose another --out or pass --force to write into it",
                    folder.display()
                );
            }
            fs::create_dir_all(folder)
                .with_context(|| format!("cannot create the run folder {}", folder.display()))?;
            Ok(folder.to_path_buf())
        }
        None => {
            let runs = Path::new("runs");
            fs::create_dir_all(runs)
                .with_context(|| format!("cannot create the folder {}", runs.display()))?;
            let stamp = humantime::format_rfc3339_millis(std::time::SystemTime::now())
                .to_string()
                .replace([':', '-'], "")
                .replace('.', "-")
                .trim_end_matches('Z')
                .to_owned();
            for attempt in 1u32.. {
                let name = match attempt {
                    1 => format!("{command}-{stamp}"),
                    n => format!("{command}-{stamp}-{n}"),
                };
                let folder = runs.join(name);
                // `create_dir` fails on an existing folder, so two runs never share one.
                match fs::create_dir(&folder) {
                    Ok(()) => return Ok(folder),
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && attempt < 1000 => {}
                    Err(e) => {
                        bail!("cannot create the run folder {}: {e}", folder.display())
                    }
                }
            }
            unreachable!("the loop returns or fails by attempt 1000")
        }
    }
}

/// [`create_run_folder`] without `--force`.
pub fn run_folder(command: &str, out: Option<&Path>) -> Result<PathBuf> {
    create_run_folder(command, out, false)
}

/// How a run ended, for the `status` entry of its JSON summary.
#[derive(Debug, Clone, PartialEq)]
pub enum RunStatus {
    Completed,
    /// Why the run stopped.
    Failed(String),
}

impl RunStatus {
    /// `{"state": "completed"}` or `{"state": "failed", "reason": ...}`.
    pub fn to_json(&self) -> serde_json::Value {
        match self {
            RunStatus::Completed => serde_json::json!({"state": "completed"}),
            RunStatus::Failed(reason) => serde_json::json!({"state": "failed", "reason": reason}),
        }
    }
}

/// A run folder and the files written into it so far.
#[derive(Debug, Clone)]
pub struct RunFolder {
    pub path: PathBuf,
    files: Vec<PathBuf>,
}

impl RunFolder {
    /// Creates the folder ([`create_run_folder`]).
    pub fn create(command: &str, out: Option<&Path>, force: bool) -> Result<Self> {
        Ok(Self {
            path: create_run_folder(command, out, force)?,
            files: Vec::new(),
        })
    }

    /// `name` inside the folder.
    pub fn join(&self, name: &str) -> PathBuf {
        self.path.join(name)
    }

    /// Records a file as written.
    pub fn record(&mut self, file: PathBuf) {
        if !self.files.contains(&file) {
            self.files.push(file);
        }
    }

    /// The files written so far, as strings for JSON.
    pub fn files(&self) -> Vec<String> {
        self.files.iter().map(|f| f.display().to_string()).collect()
    }

    /// Writes `summary.json`: `summary` (a JSON object) with `run_folder`, `status` and `files`
    /// (summary.json included) added; returns the object written.
    pub fn write_summary(
        &mut self,
        mut summary: serde_json::Value,
        status: &RunStatus,
    ) -> Result<serde_json::Value> {
        let path = self.join("summary.json");
        self.record(path.clone());
        if let Some(map) = summary.as_object_mut() {
            map.insert(
                "run_folder".to_owned(),
                self.path.display().to_string().into(),
            );
            map.insert("status".to_owned(), status.to_json());
            map.insert("files".to_owned(), self.files().into());
        }
        write_file(&path, serde_json::to_string_pretty(&summary)?)?;
        Ok(summary)
    }

    /// Runs `job`; if it fails, records the failure in `summary.json` (with what `summary`
    /// gives, and the files written so far) before passing the error on.
    pub fn run<T>(
        &mut self,
        job: impl FnOnce(&mut Self) -> Result<T>,
        summary: impl FnOnce() -> serde_json::Value,
    ) -> Result<T> {
        job(self).inspect_err(|error| {
            let reason = crate::error_line::error_line(error);
            // The job's error is the one to report; a second failure here adds nothing.
            let _ = self.write_summary(summary(), &RunStatus::Failed(reason));
        })
    }
}

/// Writes columns of equal length as CSV; headers carry the unit, e.g. `time_s`.
pub fn write_csv(path: &Path, headers: &[&str], columns: &[&[f64]]) -> Result<()> {
    if headers.len() != columns.len() {
        bail!(
            "{}: {} headers for {} columns",
            path.display(),
            headers.len(),
            columns.len()
        );
    }
    let rows = columns.first().map_or(0, |c| c.len());
    if let Some(bad) = columns.iter().position(|c| c.len() != rows) {
        bail!(
            "{}: column `{}` has {} rows, expected {rows}",
            path.display(),
            headers[bad],
            columns[bad].len()
        );
    }
    let mut text = headers.join(",");
    text.push('\n');
    for row in 0..rows {
        for (i, column) in columns.iter().enumerate() {
            if i > 0 {
                text.push(',');
            }
            let _ = write!(text, "{:.9e}", column[row]);
        }
        text.push('\n');
    }
    write_file(path, text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hsv_core::mesh::{PanelSpec, RegionKind, Surface};
    use nalgebra::Point3;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hsv-output-{}-{name}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn vtk_and_csv_round_trip_their_counts() {
        let mesh = PanelMesh::new(
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(1.0, 1.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
            ],
            &[PanelSpec::quad(0, 1, 2, 3, 0)],
            Vec::new(),
            vec![Surface::new("plate", RegionKind::Other)],
        )
        .unwrap();
        let dir = scratch("vtk");
        let displacement = vec![Vector3::new(0.0, 0.0, 1.0); 4];
        write_vtk_mesh(
            &dir.join("plate.vtk"),
            &mesh,
            &[("mode 1", &displacement)],
            &[("pressure_pa", &[101_325.0])],
        )
        .unwrap();
        let text = fs::read_to_string(dir.join("plate.vtk")).unwrap();
        assert!(text.contains("POINTS 4 double") && text.contains("POLYGONS 1 5"));
        assert!(text.contains("VECTORS mode_1 double"));
        assert!(write_vtk_mesh(&dir.join("bad.vtk"), &mesh, &[], &[("p", &[1.0, 2.0])]).is_err());

        write_csv(
            &dir.join("t.csv"),
            &["time_s", "x_m"],
            &[&[0.0, 1.0], &[2.0, 3.0]],
        )
        .unwrap();
        let csv = fs::read_to_string(dir.join("t.csv")).unwrap();
        assert_eq!(csv.lines().count(), 3);
        assert!(write_csv(&dir.join("bad.csv"), &["a", "b"], &[&[0.0], &[1.0, 2.0]]).is_err());
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn line_plot_writes_a_png() {
        let dir = scratch("png");
        let path = dir.join("plot.png");
        let plot = LinePlot {
            title: "test".into(),
            x_label: "x [m]".into(),
            y_label: "y [m]".into(),
            series: vec![Series {
                label: "y = x^2".into(),
                x: (0..10).map(f64::from).collect(),
                y: (0..10).map(|i| f64::from(i * i)).collect(),
            }],
        };
        write_line_plots_png(&path, &[plot.clone(), plot], 2, (800, 400)).unwrap();
        let bytes = fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        let _ = fs::remove_dir_all(&dir);
    }
}
