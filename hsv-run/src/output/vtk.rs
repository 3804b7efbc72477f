//! Legacy-VTK meshes of the deformed, heated vehicle with per-panel fields, and the `.pvd`
//! collection that animates them in ParaView.

use super::*;

/// Writes a panel mesh as legacy ASCII VTK polydata, with optional per-vertex vectors (e.g. a
/// mode shape's displacement, m) and per-panel scalars (e.g. pressure, Pa; temperature, K).
pub fn write_vtk_mesh(
    path: &Path,
    mesh: &PanelMesh,
    vertex_vectors: &[(&str, &[Vector3<f64>])],
    panel_scalars: &[(&str, &[f64])],
) -> Result<()> {
    write_vtk_mesh_described(
        path,
        "hsv panel mesh",
        &[],
        mesh,
        vertex_vectors,
        panel_scalars,
    )
}

/// [`write_vtk_mesh`] with a one-line `title` in the file header (what the mesh shows, e.g.
/// the mode, its frequency and the display scale) and numbers of the whole data set as VTK
/// field data (`FIELD FieldData`, read by ParaView), e.g. `("frequency_hz", 12.5)`.
pub fn write_vtk_mesh_described(
    path: &Path,
    title: &str,
    fields: &[(&str, f64)],
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
    // The legacy format allows one header line of at most 256 characters.
    let title: String = title
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .take(255)
        .collect();
    let mut text = format!("# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET POLYDATA\n");
    if !fields.is_empty() {
        let _ = writeln!(text, "FIELD FieldData {}", fields.len());
        for (name, value) in fields {
            let _ = writeln!(text, "{} 1 1 double\n{value}", vtk_name(name));
        }
    }
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
    write_file(path, text)
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
    write_file(path, text)
}
