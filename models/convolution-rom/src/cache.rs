//! The identification cache: the fingerprint of everything an identification is built from,
//! and the sealed JSON file it is saved to and reloaded from.

use std::path::Path;

use hsv_core::error::ModelError;
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{ModeShapes, PanelMesh};

use crate::identify::Identification;
use crate::{NAME, Settings};

/// Version of the cache format.
pub const FORMAT: u32 = 2;

/// FNV-1a over 64-bit words (little-endian bytes): a stable fingerprint of large inputs (mesh,
/// modes, CSV).
fn fnv1a(words: impl Iterator<Item = u64>) -> u64 {
    hsv_core::cache::fnv1a(words.flat_map(u64::to_le_bytes))
}

fn mesh_hash(mesh: &PanelMesh) -> u64 {
    let vertices = mesh
        .vertices
        .iter()
        .flat_map(|v| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]);
    let panels = mesh.panels.iter().flat_map(|p| {
        p.vertices
            .iter()
            .map(|&v| v as u64)
            .chain([u64::from(p.vertex_count), u64::from(p.surface)])
    });
    fnv1a(vertices.chain(panels))
}

fn shapes_hash(shapes: &ModeShapes) -> u64 {
    let phi = &shapes.vertex_displacement;
    fnv1a(
        [phi.nrows() as u64, phi.ncols() as u64]
            .into_iter()
            .chain(phi.iter().map(|v| v.to_bits())),
    )
}

/// What an identification is built from, as one string: the settings (the cache location
/// aside), the source's and structure's names and settings, the mesh, the mode shapes, the
/// CSV's contents and the gas.
pub(crate) fn fingerprint(
    settings: &Settings,
    source_settings: &toml::Table,
    structure_settings: &toml::Table,
    mesh: &PanelMesh,
    shapes: &ModeShapes,
    csv: Option<&str>,
    gas: &PerfectGas,
) -> Result<String, ModelError> {
    let mut identifying = settings.clone();
    identifying.cache_file.clear();
    let csv_hash = csv.map(|text| fnv1a(text.bytes().map(u64::from)));
    serde_json::to_string(&(
        FORMAT,
        &identifying,
        source_settings,
        structure_settings,
        format!("{:016x}", mesh_hash(mesh)),
        format!("{:016x}", shapes_hash(shapes)),
        csv_hash.map(|h| format!("{h:016x}")),
        gas,
    ))
    .map_err(|e| ModelError::inconsistent(NAME, format!("fingerprint: {e}")))
}

/// The cached identification at `path` if it exists, its seal matches, it was built from
/// `fingerprint` and its arrays have the shapes its counts say; a damaged one is reported and
/// rebuilt.
pub(crate) fn load(path: &Path, fingerprint: &str) -> Option<Identification> {
    let damaged = |reason: String| hsv_core::cache::CacheError::Damaged {
        path: path.to_owned(),
        reason,
    };
    match hsv_core::cache::load::<Identification>(path) {
        Ok(id) if id.format == FORMAT && id.fingerprint == fingerprint => match id.check_shapes() {
            Ok(()) => Some(id),
            Err(reason) => {
                hsv_core::cache::warn_rebuilding(&damaged(reason));
                None
            }
        },
        Ok(_) => None,
        Err(e) => {
            if e.is_damaged() {
                hsv_core::cache::warn_rebuilding(&e);
            }
            None
        }
    }
}

/// Writes `identification` to `path` as a sealed cache, atomically (regions or flutter points
/// identifying at the same time never leave a torn file).
pub(crate) fn save(path: &Path, identification: &Identification) -> Result<(), ModelError> {
    hsv_core::cache::save(path, identification)
        .map_err(|e| ModelError::inconsistent(NAME, e.to_string()))
}
