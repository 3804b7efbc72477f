//! `hsv-run vehicle`: the assembled vehicle as the analyses see it: each region with its models,
//! the mass, centre of mass and inertia summed from the structure models, each structure's
//! natural frequencies, and the reference values.

use anyhow::Result;
use clap::Args;
use hsv_core::registry::Registry;
use hsv_core::structure::MassProperties;

use super::{ConfigArg, JsonFlag, load_config};
use crate::outln;
use crate::vehicle::assemble;
use crate::vehicle::rigid::rigid_needs;

/// Arguments of `hsv-run vehicle`.
#[derive(Args, Debug, Clone)]
pub struct VehicleArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// One region as assembled.
#[derive(Debug, Clone, serde::Serialize)]
struct RegionSummary {
    region: String,
    kind: hsv_core::mesh::RegionKind,
    side: Option<hsv_core::geometry::Side>,
    panels: usize,
    models: hsv_core::config::RegionModels,
    mass_properties: Option<MassProperties>,
    natural_frequencies_hz: Vec<(String, f64)>,
}

/// Assembles the configured vehicle and prints it.
pub fn run(args: VehicleArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let sets = assemble(&loaded, &registry, &rigid_needs("hsv-run vehicle"))?;
    let mut total: Option<MassProperties> = None;
    let mut regions = Vec::new();
    for set in &sets {
        let (mass_properties, natural_frequencies_hz) = match &set.structure {
            Some(s) => {
                let mass = s.mass_properties().map(|m| m.mass_properties());
                let names = &s.modal_model().names;
                let f = s.natural_frequencies_hz()?;
                (mass, names.iter().cloned().zip(f).collect())
            }
            None => (None, Vec::new()),
        };
        if let Some(m) = &mass_properties {
            total = Some(total.map_or(*m, |t| t.combined(m)));
        }
        let mut models = set.names.clone();
        models.models.clear();
        regions.push(RegionSummary {
            region: set.info.name.clone(),
            kind: set.info.kind,
            side: set.info.side,
            panels: set.info.mesh.panels.len(),
            models,
            mass_properties,
            natural_frequencies_hz,
        });
    }
    let reference = loaded.config.reference;
    if args.json.json {
        let summary = serde_json::json!({
            "config_file": loaded.file,
            "regions": regions,
            "vehicle_mass_properties": total,
            "reference": reference,
            // `vehicle` prints; it writes no file.
            "status": crate::output::RunStatus::Completed.to_json(),
            "files": Vec::<String>::new(),
        });
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
        return Ok(());
    }
    outln!("vehicle from {}", loaded.file)?;
    for r in &regions {
        let m = &r.models;
        let names: Vec<String> = [
            ("aero", &m.aero),
            ("heat_flux", &m.heat_flux),
            ("conduction", &m.conduction),
            ("structure", &m.structure),
            ("propulsion", &m.propulsion),
        ]
        .iter()
        .filter_map(|(role, name)| name.as_ref().map(|n| format!("{role} = {n}")))
        .collect();
        outln!("\n[{}] {} panels; {}", r.region, r.panels, names.join(", "))?;
        if let Some(mp) = &r.mass_properties {
            print_mass("  ", mp)?;
        }
        for (name, f) in &r.natural_frequencies_hz {
            outln!("  {name:<28} {f:>10.3} Hz")?;
        }
    }
    if let Some(t) = &total {
        outln!("\nwhole vehicle (structures' masses summed):")?;
        print_mass("  ", t)?;
    }
    outln!(
        "\nreference: area {} m^2, chord {} m, span {} m, moment point {:?} m",
        reference.area_m2,
        reference.chord_m,
        reference.span_m,
        reference.moment_point_m
    )?;
    Ok(())
}

fn print_mass(indent: &str, m: &MassProperties) -> Result<()> {
    let c = m.center_of_mass_m;
    let i = m.inertia_kg_m2;
    outln!(
        "{indent}mass {:.1} kg, centre of mass ({:.3}, {:.3}, {:.3}) m",
        m.mass_kg,
        c.x,
        c.y,
        c.z
    )?;
    outln!(
        "{indent}inertia about it (kg m^2): Ixx {:.4e}, Iyy {:.4e}, Izz {:.4e}, Ixy {:.3e}, Ixz {:.3e}, Iyz {:.3e}",
        i[(0, 0)],
        i[(1, 1)],
        i[(2, 2)],
        i[(0, 1)],
        i[(0, 2)],
        i[(1, 2)]
    )?;
    Ok(())
}
