//! The host's propulsion adapter: engine loads and named stations.

use super::*;

/// A propulsion plugin model behind [`PropulsionModel`].
pub struct PropulsionAdapter {
    handle: Handle,
    functions: &'static PropulsionFunctions,
    mesh: MeshBuffers,
    stations: Vec<StationAbi>,
}

impl PropulsionAdapter {
    pub(crate) fn create(
        entry: &'static PluginModel,
        functions: &'static PropulsionFunctions,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Self, ModelError> {
        Ok(Self {
            handle: Handle::create(entry, name, context)?,
            functions,
            mesh: MeshBuffers::default(),
            stations: Vec::new(),
        })
    }
}

pub(super) fn engine_status(code: u32) -> Option<EngineStatus> {
    Some(match code {
        ENGINE_OK => EngineStatus::Ok,
        ENGINE_SPILLAGE => EngineStatus::Spillage,
        ENGINE_THERMAL_CHOKING => EngineStatus::ThermalChoking,
        ENGINE_UNSTART => EngineStatus::Unstart,
        _ => return None,
    })
}

impl PropulsionModel for PropulsionAdapter {
    fn name(&self) -> &str {
        &self.handle.name
    }

    fn evaluate(
        &mut self,
        inputs: &EngineInputs<'_>,
        out: &mut PropulsionSolution,
    ) -> Result<(), ModelError> {
        let name = &self.handle.name;
        let n = inputs.body.panels.len();
        self.mesh.fill(inputs.body);
        let input = EngineInputAbi {
            flight: flight_abi(inputs.flight),
            body: self.mesh.abi(),
            fuel_equivalence_ratio: inputs.fuel_equivalence_ratio,
        };
        out.panel_pressure_pa.clear();
        out.panel_pressure_pa.resize(n, 0.0);
        let blank = StationAbi {
            name: [0; STATION_NAME_BYTES],
            mach: 0.0,
            pressure_pa: 0.0,
            temperature_k: 0.0,
        };
        self.stations.clear();
        self.stations.resize(STATION_CAPACITY, blank);
        let mut output = EngineOutputAbi {
            loads: [0.0; 6],
            mass_flow_kg_s: 0.0,
            status: ENGINE_OK,
            panel_pressure_pa: out.panel_pressure_pa.as_mut_ptr(),
            stations: self.stations.as_mut_ptr(),
            station_capacity: STATION_CAPACITY,
            n_stations: 0,
        };
        // SAFETY: n panel pressures and STATION_CAPACITY stations of room.
        let status = unsafe { (self.functions.evaluate)(self.handle.raw, &input, &mut output) };
        self.handle.check(status, "evaluation")?;
        check_finite(name, "engine load", &output.loads, 6, "loads")?;
        check_finite(name, "mass flow", &[output.mass_flow_kg_s], 1, "inlet")?;
        check_finite(name, "panel pressure", &out.panel_pressure_pa, 1, "panel")?;
        if output.n_stations > STATION_CAPACITY {
            return Err(ModelError::inconsistent(
                name,
                format!(
                    "plugin reported {} stations, more than the {STATION_CAPACITY} it had room for",
                    output.n_stations
                ),
            ));
        }
        let l = output.loads;
        out.loads = Loads {
            force_n: Vector3::new(l[0], l[1], l[2]),
            moment_nm: Vector3::new(l[3], l[4], l[5]),
        };
        out.mass_flow_kg_s = output.mass_flow_kg_s;
        out.status = engine_status(output.status).ok_or_else(|| {
            ModelError::inconsistent(
                name,
                format!("plugin engine status code {} is not 0-3", output.status),
            )
        })?;
        out.stations.truncate(output.n_stations);
        for (k, station) in self.stations[..output.n_stations].iter().enumerate() {
            let end = station
                .name
                .iter()
                .position(|&b| b == 0)
                .unwrap_or(STATION_NAME_BYTES);
            let label = String::from_utf8_lossy(&station.name[..end]);
            let values = [station.mach, station.pressure_pa, station.temperature_k];
            check_finite(
                name,
                &format!("station `{label}` state"),
                &values,
                3,
                "station",
            )?;
            // Reuse the slot (and its name's allocation) when the station is the same.
            if out.stations.get(k).is_none_or(|slot| slot.station != label) {
                let state = StationState {
                    station: label.into_owned(),
                    mach: 0.0,
                    pressure_pa: 0.0,
                    temperature_k: 0.0,
                };
                match out.stations.get_mut(k) {
                    Some(slot) => *slot = state,
                    None => out.stations.push(state),
                }
            }
            let slot = &mut out.stations[k];
            slot.mach = station.mach;
            slot.pressure_pa = station.pressure_pa;
            slot.temperature_k = station.temperature_k;
        }
        Ok(())
    }
}
