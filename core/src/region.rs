//! A region as its models see it: name, kind, side, geometry, undeformed mesh and the settings of
//! every model in it (global `[models.X]` overlaid by `[regions.<region>.models.X]`).
//!
//! The runner builds one [`RegionInfo`] per region at assembly and hands it to every model it
//! constructs there, so a model never reads the vehicle config's raw tables and the left and right
//! lifting surfaces are two regions with their own models.

use std::collections::BTreeMap;

use crate::aero::ReferenceValues;
use crate::error::ModelError;
use crate::gas::PerfectGas;
use crate::geometry::{GeometryConfig, LiftingSurfaceConfig, Side, VerticalFinConfig};
use crate::mesh::{PanelMesh, RegionKind};

/// The parametric geometry a region was built from, for models that build their own grids.
#[derive(Debug, Clone, PartialEq)]
pub enum RegionGeometry {
    /// The main body (and the engine under it): the `[geometry]` table.
    Body(GeometryConfig),
    /// One all-movable lifting surface: the `[lifting_surface]` planform on `side`.
    LiftingSurface {
        planform: LiftingSurfaceConfig,
        side: Side,
    },
    /// The fixed vertical fin: the `[vertical_fin]` planform on the upper centreline.
    VerticalFin(VerticalFinConfig),
    /// A mesh with no parametric description (an STL file).
    Mesh,
}

/// One model's settings as a region sees them, and where they come from (for messages).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelSettings {
    pub table: toml::Table,
    /// `models.X`, or `regions.R.models.X` when the region overrides the global table.
    pub key_path: String,
}

/// Everything a model constructor may know about the region it is built for.
#[derive(Debug, Clone)]
pub struct RegionInfo {
    /// The region's config name: `main_body`, `left_surface`, `right_surface`, `propulsion`,
    /// `vertical_fin`.
    pub name: String,
    pub kind: RegionKind,
    /// Which side, for a lifting surface.
    pub side: Option<Side>,
    pub geometry: RegionGeometry,
    /// The region's undeformed wetted mesh, body axes, m (the whole body for the propulsion
    /// region, whose engine reads the panels tagged [`RegionKind::Propulsion`]).
    pub mesh: PanelMesh,
    pub reference: ReferenceValues,
    pub gas: PerfectGas,
    /// The config file, for messages.
    pub file: String,
    /// Settings of every model named in the config, as this region sees them.
    pub settings: BTreeMap<String, ModelSettings>,
}

impl RegionInfo {
    /// A region around an arbitrary mesh (an STL file, a test plate): no parametric geometry and
    /// no model settings beyond `settings`.
    pub fn standalone(
        name: &str,
        mesh: PanelMesh,
        reference: ReferenceValues,
        gas: PerfectGas,
        file: &str,
    ) -> Self {
        Self {
            name: name.to_owned(),
            kind: RegionKind::Other,
            side: None,
            geometry: RegionGeometry::Mesh,
            mesh,
            reference,
            gas,
            file: file.to_owned(),
            settings: BTreeMap::new(),
        }
    }

    /// The settings of model `name` in this region (an empty table at `models.<name>` if the
    /// config has none).
    pub fn model_settings(&self, name: &str) -> ModelSettings {
        self.settings
            .get(name)
            .cloned()
            .unwrap_or_else(|| ModelSettings {
                table: toml::Table::new(),
                key_path: format!("models.{name}"),
            })
    }

    /// The planform and side of a lifting-surface region; other regions are an error naming the
    /// region and what `model` needed.
    pub fn lifting_surface(
        &self,
        model: &str,
    ) -> Result<(&LiftingSurfaceConfig, Side), ModelError> {
        match &self.geometry {
            RegionGeometry::LiftingSurface { planform, side } => Ok((planform, *side)),
            _ => Err(self.wrong_geometry(model, "a lifting-surface planform")),
        }
    }

    /// The body geometry of a main-body or propulsion region; other regions are an error naming
    /// the region and what `model` needed.
    pub fn body_geometry(&self, model: &str) -> Result<&GeometryConfig, ModelError> {
        match &self.geometry {
            RegionGeometry::Body(geometry) => Ok(geometry),
            _ => Err(self.wrong_geometry(model, "the body geometry ([geometry] table)")),
        }
    }

    fn wrong_geometry(&self, model: &str, needed: &str) -> ModelError {
        let has = match &self.geometry {
            RegionGeometry::Body(_) => "the body geometry",
            RegionGeometry::LiftingSurface { .. } => "a lifting-surface planform",
            RegionGeometry::VerticalFin(_) => "a vertical-fin planform",
            RegionGeometry::Mesh => "a mesh without parametric geometry",
        };
        ModelError::WrongRegion {
            model: model.to_owned(),
            message: format!(
                "region `{}` has {has}, but the model needs {needed}",
                self.name
            ),
        }
    }
}

/// Overlays `over` on `base`, key by key (nested tables merged, other values replaced).
pub fn merge_tables(base: &mut toml::Table, over: &toml::Table) {
    for (key, value) in over {
        match (base.get_mut(key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge_tables(b, o),
            _ => {
                base.insert(key.clone(), value.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_replace_keys_and_merge_nested_tables() {
        let mut base: toml::Table =
            toml::from_str("a = 1\nb = 2\n[c]\nx = 1\ny = 2").expect("toml");
        let over: toml::Table = toml::from_str("b = 3\n[c]\ny = 4").expect("toml");
        merge_tables(&mut base, &over);
        let want: toml::Table = toml::from_str("a = 1\nb = 3\n[c]\nx = 1\ny = 4").expect("toml");
        assert_eq!(base, want);
    }
}
