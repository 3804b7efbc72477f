//! Run outputs: run folders, CSV time histories, PNG line plots and VTK meshes for ParaView.
//!
//! Every command that writes files goes through here, so all runs look alike: one folder per run
//! (`runs/<command>-<UTC time>/` unless `--out` names one), CSV with units in the headers, PNG
//! plots of what the paper plots, legacy-VTK meshes plus a `.pvd` collection to animate them.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use anyhow::{Context, Result, bail};
use hsv_core::mesh::PanelMesh;
use nalgebra::Vector3;
use plotters::prelude::*;

/// Creates the run folder: `out` if given, else `runs/<command>-<UTC time>`.
pub fn run_folder(command: &str, out: Option<&Path>) -> Result<PathBuf> {
    let folder = match out {
        Some(path) => path.to_path_buf(),
        None => {
            let stamp = humantime::format_rfc3339_seconds(std::time::SystemTime::now())
                .to_string()
                .replace([':', '-'], "")
                .trim_end_matches('Z')
                .to_owned();
            PathBuf::from("runs").join(format!("{command}-{stamp}"))
        }
    };
    fs::create_dir_all(&folder)
        .with_context(|| format!("cannot create the run folder {}", folder.display()))?;
    Ok(folder)
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
    fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// One line of a plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

/// One panel of a figure: title, axis labels (with units) and its lines.
#[derive(Debug, Clone, PartialEq)]
pub struct LinePlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// Font for plot text: DejaVu Sans from the system (Debian `fonts-dejavu-core`), registered once.
fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    let outcome = REGISTERED.get_or_init(|| {
        const CANDIDATES: [&str; 3] = [
            "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
            "/usr/share/fonts/TTF/DejaVuSans.ttf",
            "/usr/share/fonts/dejavu/DejaVuSans.ttf",
        ];
        let bytes = CANDIDATES
            .iter()
            .find_map(|p| fs::read(p).ok())
            .ok_or_else(|| {
                format!(
                    "no plot font found (looked for {}); install Debian's fonts-dejavu-core",
                    CANDIDATES.join(", ")
                )
            })?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| "the DejaVu Sans font file could not be parsed".to_owned())
    });
    outcome.clone().map_err(anyhow::Error::msg)
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
];

/// Axis range covering every finite value, padded by 5 % (and made non-empty).
fn padded_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        0.05 * span
    } else {
        0.05 * lo.abs().max(1.0)
    };
    (lo - pad)..(hi + pad)
}

/// Draws `plots` as a grid of `columns` panels into a PNG of `width` × `height` pixels.
pub fn write_line_plots_png(
    path: &Path,
    plots: &[LinePlot],
    columns: usize,
    (width, height): (u32, u32),
) -> Result<()> {
    if plots.is_empty() {
        bail!("{}: nothing to plot", path.display());
    }
    register_font()?;
    let columns = columns.clamp(1, plots.len());
    let rows = plots.len().div_ceil(columns);
    let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
    let draw = || -> std::result::Result<(), Box<dyn std::error::Error>> {
        root.fill(&WHITE)?;
        let areas = root.split_evenly((rows, columns));
        for (plot, area) in plots.iter().zip(areas.iter()) {
            let x_range = padded_range(plot.series.iter().flat_map(|s| s.x.iter().copied()));
            let y_range = padded_range(plot.series.iter().flat_map(|s| s.y.iter().copied()));
            let mut chart = ChartBuilder::on(area)
                .caption(&plot.title, ("sans-serif", 18))
                .margin(8)
                .x_label_area_size(36)
                .y_label_area_size(64)
                .build_cartesian_2d(x_range, y_range)?;
            chart
                .configure_mesh()
                .x_desc(plot.x_label.as_str())
                .y_desc(plot.y_label.as_str())
                .label_style(("sans-serif", 12))
                .draw()?;
            for (i, series) in plot.series.iter().enumerate() {
                let color = PALETTE[i % PALETTE.len()];
                let points = series
                    .x
                    .iter()
                    .zip(&series.y)
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .map(|(&x, &y)| (x, y));
                chart
                    .draw_series(LineSeries::new(points, color.stroke_width(2)))?
                    .label(series.label.as_str())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                    });
            }
            if plot.series.iter().any(|s| !s.label.is_empty()) {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 12))
                    .draw()?;
            }
        }
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| anyhow::anyhow!("cannot draw {}: {e}", path.display()))
}

/// Writes a panel mesh as legacy ASCII VTK polydata, with optional per-vertex vectors (e.g. a
/// mode shape's displacement, m) and per-panel scalars (e.g. pressure, Pa; temperature, K).
pub fn write_vtk_mesh(
    path: &Path,
    mesh: &PanelMesh,
    vertex_vectors: &[(&str, &[Vector3<f64>])],
    panel_scalars: &[(&str, &[f64])],
) -> Result<()> {
    for (name, values) in vertex_vectors {
        if values.len() != mesh.vertices.len() {
            bail!(
                "{}: vertex field `{name}` has {} values for {} vertices",
                path.display(),
                values.len(),
                mesh.vertices.len()
            );
        }
    }
    for (name, values) in panel_scalars {
        if values.len() != mesh.panels.len() {
            bail!(
                "{}: panel field `{name}` has {} values for {} panels",
                path.display(),
                values.len(),
                mesh.panels.len()
            );
        }
    }
    let mut text =
        String::from("# vtk DataFile Version 3.0\nhsv panel mesh\nASCII\nDATASET POLYDATA\n");
    let _ = writeln!(text, "POINTS {} double", mesh.vertices.len());
    for v in &mesh.vertices {
        let _ = writeln!(text, "{} {} {}", v.x, v.y, v.z);
    }
    let connectivity: usize = mesh
        .panels
        .iter()
        .map(|p| 1 + p.vertex_indices().len())
        .sum();
    let _ = writeln!(text, "POLYGONS {} {connectivity}", mesh.panels.len());
    for panel in &mesh.panels {
        let ids = panel.vertex_indices();
        let _ = write!(text, "{}", ids.len());
        for id in ids {
            let _ = write!(text, " {id}");
        }
        text.push('\n');
    }
    if !vertex_vectors.is_empty() {
        let _ = writeln!(text, "POINT_DATA {}", mesh.vertices.len());
        for (name, values) in vertex_vectors {
            let _ = writeln!(text, "VECTORS {} double", vtk_name(name));
            for v in *values {
                let _ = writeln!(text, "{} {} {}", v.x, v.y, v.z);
            }
        }
    }
    let _ = writeln!(text, "CELL_DATA {}", mesh.panels.len());
    let _ = writeln!(text, "SCALARS surface int 1\nLOOKUP_TABLE default");
    for panel in &mesh.panels {
        let _ = writeln!(text, "{}", panel.surface);
    }
    for (name, values) in panel_scalars {
        let _ = writeln!(
            text,
            "SCALARS {} double 1\nLOOKUP_TABLE default",
            vtk_name(name)
        );
        for v in *values {
            let _ = writeln!(text, "{v}");
        }
    }
    fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// VTK field names cannot contain white space.
fn vtk_name(name: &str) -> String {
    name.split_whitespace().collect::<Vec<_>>().join("_")
}

/// Writes a ParaView collection (`.pvd`) listing `(time_s, file)` pairs, so a VTK series
/// animates in time; file paths are relative to the `.pvd`.
pub fn write_pvd(path: &Path, entries: &[(f64, &str)]) -> Result<()> {
    let mut text = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n",
    );
    for (time, file) in entries {
        let _ = writeln!(
            text,
            "    <DataSet timestep=\"{time}\" group=\"\" part=\"0\" file=\"{file}\"/>"
        );
    }
    text.push_str("  </Collection>\n</VTKFile>\n");
    fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
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
