//! In-flight heating of the lifting surfaces: its start, its advance to a time, and the
//! temperatures and deformed, heated OML the outputs show.

use super::*;

impl PartitionedVehicle {
    /// Starts every heated surface at a uniform temperature with `rates` (call before flying).
    pub fn start_heating(&mut self, rates: &HeatingRates) -> Result<(), VehicleError> {
        self.heating = *rates;
        // The heat-flux topics at the new rate, nothing published: the first step refreshes.
        self.rebuild_exchange()?;
        for s in &mut self.surfaces {
            if let Some(t) = &mut s.thermal {
                t.region
                    .start(rates.initial_k)
                    .map_err(model_error(&s.name))?;
                t.stiffness_time_s = 0.0;
            }
        }
        Ok(())
    }

    /// Advances every heated surface to `time_s`: its thermal region's conduction steps under
    /// the heat flux of the step's start ([`Self::begin_step`]) and, every stiffness interval,
    /// the temperature field published on its `structure_temperatures` topic, which its
    /// structure reads into its stiffness (and the modal equations follow).
    pub(super) fn advance_heating(&mut self, time_s: f64) -> Result<(), VehicleError> {
        let rates = self.heating;
        let exchange = &self.exchange;
        // Each surface heats on its own (conduction, the field onto its structure): side by side.
        let heat = |(i, s): (usize, &mut Surface)| heat_surface(s, exchange, i, time_s, &rates);
        if side_by_side() {
            self.surfaces
                .par_iter_mut()
                .enumerate()
                .try_for_each(heat)?;
        } else {
            self.surfaces.iter_mut().enumerate().try_for_each(heat)?;
        }
        for (i, s) in self.surfaces.iter().enumerate() {
            if let Some(t) = &s.thermal
                && t.stiffness_changed
            {
                self.exchange.publish_structure_temperatures(
                    i,
                    time_s,
                    &t.onto_structure.mean_k,
                    &t.onto_structure.difference_k,
                )?;
            }
        }
        // Each structure reads its field (a stiffness update: side by side).
        let exchange = &self.exchange;
        let read = |(i, s): (usize, &mut Surface)| read_structure_temperatures(s, exchange, i);
        if side_by_side() {
            self.surfaces
                .par_iter_mut()
                .enumerate()
                .try_for_each(read)?;
        } else {
            self.surfaces.iter_mut().enumerate().try_for_each(read)?;
        }
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            if let Some(t) = &mut s.thermal
                && std::mem::take(&mut t.stiffness_changed)
            {
                self.dynamics
                    .set_surface_matrices(i, s.structure.modal_model())?;
            }
        }
        Ok(())
    }

    /// Structure temperatures of each heated surface (empty for unheated surfaces).
    pub fn surface_temperatures(&mut self) -> Vec<(String, SurfaceTemperatures)> {
        let mut out = Vec::new();
        self.each_surface_temperature(|name, t| out.push((name.to_owned(), t)));
        out
    }

    /// Lowest, highest and mean (of the surfaces' means) structure temperature over every
    /// heated surface, K; None when no surface heats. Allocates nothing (the time loop's record).
    pub fn heated_surface_range(&mut self) -> Option<SurfaceTemperatures> {
        let mut range: Option<SurfaceTemperatures> = None;
        let mut n = 0.0;
        self.each_surface_temperature(|_, t| {
            n += 1.0;
            range = Some(match range {
                None => t,
                Some(r) => SurfaceTemperatures {
                    min_k: r.min_k.min(t.min_k),
                    max_k: r.max_k.max(t.max_k),
                    mean_k: r.mean_k + (t.mean_k - r.mean_k) / n,
                },
            });
        });
        range
    }

    /// Each heated surface's name and temperatures.
    pub(super) fn each_surface_temperature(
        &mut self,
        mut visit: impl FnMut(&str, SurfaceTemperatures),
    ) {
        for s in &mut self.surfaces {
            if let Some(t) = &mut s.thermal {
                let node_k = t.region.node_temperatures_k();
                let n = node_k.len().max(1) as f64;
                visit(
                    &s.name,
                    SurfaceTemperatures {
                        min_k: node_k.iter().copied().fold(f64::INFINITY, f64::min),
                        max_k: node_k.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                        mean_k: node_k.iter().sum::<f64>() / n,
                    },
                );
            }
        }
    }

    /// The vehicle's OML as last evaluated (body deformed by its modes, surfaces deformed and
    /// deflected) merged into one mesh, with the absolute pressure (Pa) and, for heated surfaces,
    /// the wall temperature (K; NaN elsewhere) of each panel: what a VTK frame shows.
    pub fn oml_snapshot(&mut self) -> (PanelMesh, Vec<f64>, Vec<f64>) {
        let mut mesh = self.body.mesh.clone();
        let mut pressure = self.body.solution.pressure_pa.clone();
        let mut wall = vec![f64::NAN; mesh.panels.len()];
        for s in &mut self.surfaces {
            mesh.merge(&s.deflected);
            pressure.extend_from_slice(&s.solution.pressure_pa);
            match &mut s.thermal {
                Some(t) => wall.extend_from_slice(t.region.wall_temperatures_k()),
                None => wall.extend(std::iter::repeat_n(f64::NAN, s.deflected.panels.len())),
            }
        }
        for f in &self.followers {
            mesh.merge(f.flown_mesh());
            pressure.extend_from_slice(&f.solution.pressure_pa);
            wall.extend(std::iter::repeat_n(f64::NAN, f.flown_mesh().panels.len()));
        }
        pressure.resize(mesh.panels.len(), f64::NAN);
        (mesh, pressure, wall)
    }
}
