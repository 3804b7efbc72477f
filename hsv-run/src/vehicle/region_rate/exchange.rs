//! The regions' publications exchanged through the data manager ([`hsv_core::data`]): the
//! topics of [`RegionExchange`] (one predicted loads topic per region, the body's skin friction,
//! each lifting surface's wall heat flux) and the in-place publish and read of each; their
//! values are [`super::published`]'s, when a region is due is [`super::RegionLoadRate`]'s rule
//! (module docs of [`super`]).

use hsv_core::aero::Loads;
use hsv_core::data::{
    DataCheckpoint, DataError, DataManager, DataManagerBuilder, Publisher, Subscriber,
};
use nalgebra::DVector;

use super::RegionLoadRate;
use super::published::{PublishedFriction, PublishedLoads, PublishedTemperatures};

/// The reader of every topic: the coupled derivative, which assembles the vehicle's loads.
const READER: &str = "coupling";

/// A publisher and its reader.
type Channel<T> = (Publisher<T>, Subscriber<T>);

/// A region's loads topic: its publisher, its reader and its name (for errors).
struct LoadsChannel {
    publisher: Publisher<PublishedLoads>,
    reader: Subscriber<PublishedLoads>,
    topic: String,
}

impl LoadsChannel {
    /// The predicted topic `topic` published by `region` every `period_s` and read by the
    /// coupling.
    fn new(
        builder: &mut DataManagerBuilder,
        region: &str,
        topic: String,
        period_s: f64,
    ) -> Result<Self, DataError> {
        Ok(Self {
            publisher: builder.publish_predicted(region, &topic, period_s)?,
            reader: builder.subscribe(READER, &topic)?,
            topic,
        })
    }
}

/// The regions' publications at their own rates, exchanged through the data manager (paper
/// §III): one predicted topic per region (`main_body/loads`, `<surface>/loads`) and the body's
/// skin friction (`main_body/skin_friction`), each keeping its last two converged values and
/// read at any stage time by the module's predictor; and each lifting surface's wall heat flux
/// (`<surface>/wall_heat_flux`, W/m² per panel), published by the aerothermal step every
/// heat-flux interval (paper Table 3: 10 ms) and held for the conduction steps between (1 ms).
/// Handles are indices: no look-up and, once each topic has its values, no allocation in the
/// time loop.
pub struct RegionExchange {
    data: DataManager,
    /// The exchange with nothing published: what forgetting restores.
    empty: DataCheckpoint,
    body: LoadsChannel,
    friction: Channel<PublishedFriction>,
    surfaces: Vec<LoadsChannel>,
    heat_fluxes: Vec<Channel<Vec<f64>>>,
    /// Each surface's structure temperatures (`<surface>/structure_temperatures`), published by
    /// its thermal region at every stiffness update and read by its structure.
    structure_temperatures: Vec<Channel<PublishedTemperatures>>,
    /// The value a read fills before it is copied out (no allocation after the first).
    scratch: PublishedLoads,
}

impl std::fmt::Debug for RegionExchange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RegionExchange")
            .field("data", &self.data)
            .finish_non_exhaustive()
    }
}

/// How a region's evaluation enters its loads topic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Publication {
    /// At an accepted state where the region falls due at its own rate: committed to the history
    /// the predictor extrapolates over the stages until the region's next evaluation.
    Converged,
    /// One derivative's evaluation (a stage, a trim or linearization point): the topic's
    /// iterate, read at once by the coupling (`read_*_latest`), never extrapolated and never in
    /// the history.
    Iterate,
}

/// A region's loads topic and its latest publication ([`RegionExchange::loads_publications`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LoadsPublication {
    pub topic: String,
    /// Time of the latest publication, s (None: nothing published).
    pub time_s: Option<f64>,
    /// Whether it was published converged, at an accepted state where the region fell due
    /// (else it is one derivative's iterate).
    pub converged: bool,
    /// Its force, N, body axes (the body: all its loads about the centre of mass; a surface:
    /// its applied load in its own frame).
    pub force_n: nalgebra::Vector3<f64>,
}

/// The period a topic declares for a rate, s: its interval, or (every stage: never published)
/// the shortest one that passes the data manager's check.
fn declared_period_s(rate: RegionLoadRate) -> f64 {
    match rate {
        RegionLoadRate::Interval(interval_s) => interval_s,
        RegionLoadRate::EveryStage => f64::MIN_POSITIVE,
    }
}

impl RegionExchange {
    /// The topics of the body (at `body` rate, its skin friction at `friction`'s among them)
    /// and of each surface named in `surfaces` (at `surface` rate, its wall heat flux every
    /// `heat_flux_period_s`), nothing published.
    pub fn new(
        surface_names: &[String],
        body: RegionLoadRate,
        friction: RegionLoadRate,
        surface: RegionLoadRate,
        heat_flux_period_s: f64,
    ) -> Result<Self, DataError> {
        let mut builder = DataManagerBuilder::new();
        let body_period_s = declared_period_s(body);
        // The friction is published only at the body's publications where it is due.
        let friction_period_s = match friction {
            RegionLoadRate::Interval(interval_s) => interval_s.max(body_period_s),
            RegionLoadRate::EveryStage => body_period_s,
        };
        let body = LoadsChannel::new(
            &mut builder,
            "main_body",
            "main_body/loads".to_owned(),
            body_period_s,
        )?;
        let friction = (
            builder.publish_predicted("main_body", "main_body/skin_friction", friction_period_s)?,
            builder.subscribe(READER, "main_body/skin_friction")?,
        );
        let surfaces = surface_names
            .iter()
            .map(|name| {
                let topic = format!("{name}/loads");
                LoadsChannel::new(&mut builder, name, topic, declared_period_s(surface))
            })
            .collect::<Result<Vec<_>, DataError>>()?;
        let heat_fluxes = surface_names
            .iter()
            .map(|name| {
                let topic = format!("{name}/wall_heat_flux");
                Ok((
                    builder.publish_with_rate(name, &topic, heat_flux_period_s)?,
                    builder.subscribe(READER, &topic)?,
                ))
            })
            .collect::<Result<Vec<_>, DataError>>()?;
        let structure_temperatures = surface_names
            .iter()
            .map(|name| {
                let topic = format!("{name}/structure_temperatures");
                Ok((
                    builder.publish(&format!("{name}/thermal"), &topic)?,
                    builder.subscribe(name, &topic)?,
                ))
            })
            .collect::<Result<Vec<_>, DataError>>()?;
        let data = builder.build()?;
        Ok(Self {
            empty: data.checkpoint(),
            data,
            body,
            friction,
            surfaces,
            heat_fluxes,
            structure_temperatures,
            scratch: PublishedLoads::default(),
        })
    }

    /// The time of the first surface's latest wall heat flux, s (the heated surfaces' fluxes
    /// are refreshed together).
    pub fn heat_flux_time_s(&self) -> Option<f64> {
        let (_, reader) = self.heat_fluxes.first()?;
        self.data.read_converged(*reader).ok().map(|s| s.time_s)
    }

    /// Publishes surface `index`'s wall heat flux (W/m² per panel) at `time_s`, in place.
    pub fn publish_heat_flux(
        &mut self,
        index: usize,
        time_s: f64,
        flux_w_m2: &[f64],
    ) -> Result<(), DataError> {
        let Some(&(publisher, _)) = self.heat_fluxes.get(index) else {
            return Ok(());
        };
        self.data
            .publish_with(publisher, time_s, |v: &mut Vec<f64>| {
                v.clear();
                v.extend_from_slice(flux_w_m2);
            })?;
        self.data.mark_converged(publisher)?;
        Ok(())
    }

    /// Surface `index`'s latest published wall heat flux, W/m² per panel, read in place (held
    /// until the next refresh, which comes at a step's start before that step's conduction);
    /// None before the first.
    pub fn heat_flux(&self, index: usize) -> Result<Option<&[f64]>, DataError> {
        let Some(&(_, reader)) = self.heat_fluxes.get(index) else {
            return Ok(None);
        };
        match self.data.read_converged(reader) {
            Ok(latest) => Ok(Some(latest.value.as_slice())),
            Err(DataError::NothingConverged { .. }) => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// Publishes surface `index`'s structure temperatures (K per structure node: mean and face
    /// difference) at `time_s`, in place.
    pub fn publish_structure_temperatures(
        &mut self,
        index: usize,
        time_s: f64,
        mean_k: &[f64],
        difference_k: &[f64],
    ) -> Result<(), DataError> {
        let Some(&(publisher, _)) = self.structure_temperatures.get(index) else {
            return Ok(());
        };
        self.data
            .publish_with(publisher, time_s, |t: &mut PublishedTemperatures| {
                t.mean_k.clear();
                t.mean_k.extend_from_slice(mean_k);
                t.difference_k.clear();
                t.difference_k.extend_from_slice(difference_k);
            })?;
        self.data.mark_converged(publisher)?;
        Ok(())
    }

    /// Surface `index`'s latest structure temperatures and their time, read in place; None
    /// before the first.
    pub fn structure_temperatures(
        &self,
        index: usize,
    ) -> Result<Option<(f64, &PublishedTemperatures)>, DataError> {
        let Some(&(_, reader)) = self.structure_temperatures.get(index) else {
            return Ok(None);
        };
        match self.data.read_converged(reader) {
            Ok(latest) => Ok(Some((latest.time_s, latest.value))),
            Err(DataError::NothingConverged { .. }) => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// Forgets every publication (a new run).
    pub fn clear(&mut self) -> Result<(), DataError> {
        self.data.restore(&self.empty)
    }

    /// The exchange's state, for a restart file.
    pub fn checkpoint(&self) -> DataCheckpoint {
        self.data.checkpoint()
    }

    /// Restores a state of [`Self::checkpoint`] (of an exchange with the same topics).
    pub fn restore(&mut self, checkpoint: &DataCheckpoint) -> Result<(), DataError> {
        self.data.restore(checkpoint)
    }

    /// Each region's loads topic (the body's, then each surface's) with its latest
    /// publication, if any: what the coupling read last.
    pub fn loads_publications(&self) -> Vec<LoadsPublication> {
        std::iter::once(&self.body)
            .chain(&self.surfaces)
            .map(|channel| {
                let latest = self.data.read(channel.reader).ok();
                LoadsPublication {
                    topic: channel.topic.clone(),
                    time_s: latest.as_ref().map(|l| l.time_s),
                    converged: latest.as_ref().is_some_and(|l| l.converged),
                    force_n: latest.map_or_else(Default::default, |l| l.value.force_n),
                }
            })
            .collect()
    }

    /// The time of the body's latest publication, s.
    pub fn body_time_s(&self) -> Option<f64> {
        self.data
            .read_converged(self.body.reader)
            .ok()
            .map(|s| s.time_s)
    }

    /// The time of the first surface's latest publication, s (the surfaces publish together).
    pub fn surfaces_time_s(&self) -> Option<f64> {
        let surface = self.surfaces.first()?;
        self.data
            .read_converged(surface.reader)
            .ok()
            .map(|s| s.time_s)
    }

    /// Publishes the body's loads at `time_s`, converged or as an iterate ([`Publication`]).
    pub fn publish_body(
        &mut self,
        at: (f64, Publication),
        total: &Loads,
        aero: &Loads,
        generalized: &[f64],
    ) -> Result<(), DataError> {
        publish_loads(
            &mut self.data,
            self.body.publisher,
            at,
            total,
            aero,
            generalized,
        )
    }

    /// The body's latest publication (the iterate just published, or the converged one) into
    /// the outputs.
    pub fn read_body_latest(
        &self,
        total: &mut Loads,
        aero: &mut Loads,
        generalized: &mut [f64],
    ) -> Result<(), DataError> {
        read_latest_loads(&self.data, &self.body, total, Some(aero), generalized)
    }

    /// Publishes surface `index`'s applied loads about its pivot (its own frame) and aero
    /// generalized forces at `time_s`, converged or as an iterate ([`Publication`]).
    pub fn publish_surface(
        &mut self,
        index: usize,
        at: (f64, Publication),
        applied: &Loads,
        generalized: &[f64],
    ) -> Result<(), DataError> {
        let Some(surface) = self.surfaces.get(index) else {
            return Ok(());
        };
        let none = Loads::default();
        publish_loads(
            &mut self.data,
            surface.publisher,
            at,
            applied,
            &none,
            generalized,
        )
    }

    /// Surface `index`'s latest publication into the outputs (as [`Self::read_body_latest`]).
    pub fn read_surface_latest(
        &self,
        index: usize,
        applied: &mut Loads,
        generalized: &mut [f64],
    ) -> Result<(), DataError> {
        let Some(surface) = self.surfaces.get(index) else {
            return Ok(());
        };
        read_latest_loads(&self.data, surface, applied, None, generalized)
    }

    /// The body's loads at `time_s` into the outputs (module docs' predictor; held with one
    /// publication); false (outputs untouched) with none. A publication whose generalized
    /// forces are not `generalized.len()` long is refused ([`DataError::LengthMismatch`]).
    pub fn read_body(
        &mut self,
        time_s: f64,
        total: &mut Loads,
        aero: &mut Loads,
        generalized: &mut [f64],
    ) -> Result<bool, DataError> {
        read_loads(
            &self.data,
            &self.body,
            &mut self.scratch,
            time_s,
            total,
            Some(aero),
            generalized,
        )
    }

    /// Surface `index`'s applied loads and aero generalized forces at `time_s` (as
    /// [`Self::read_body`]).
    pub fn read_surface(
        &mut self,
        index: usize,
        time_s: f64,
        applied: &mut Loads,
        generalized: &mut [f64],
    ) -> Result<bool, DataError> {
        let Some(surface) = self.surfaces.get(index) else {
            return Ok(false);
        };
        read_loads(
            &self.data,
            surface,
            &mut self.scratch,
            time_s,
            applied,
            None,
            generalized,
        )
    }

    /// Publishes the body's skin friction evaluated at `time_s`.
    pub fn publish_friction(&mut self, time_s: f64, loads: &Loads) -> Result<(), DataError> {
        self.data.publish(
            self.friction.0,
            time_s,
            PublishedFriction {
                force_n: loads.force_n,
                moment_nm: loads.moment_nm,
            },
        )?;
        self.data.mark_converged(self.friction.0)?;
        Ok(())
    }

    /// The skin friction at `time_s`, extrapolated linearly from its last two evaluations (held
    /// with one), when `rate` says it is not due; None when it is.
    pub fn friction_at(
        &self,
        time_s: f64,
        rate: &RegionLoadRate,
    ) -> Result<Option<Loads>, DataError> {
        let reader = self.friction.1;
        let last_s = match self.data.read_converged(reader) {
            Ok(latest) => latest.time_s,
            Err(DataError::NothingConverged { .. }) => return Ok(None),
            Err(e) => return Err(e),
        };
        if rate.is_due(time_s, Some(last_s)) {
            return Ok(None);
        }
        let mut friction = PublishedFriction::default();
        self.data.read_at(reader, time_s, &mut friction)?;
        Ok(Some(Loads {
            force_n: friction.force_n,
            moment_nm: friction.moment_nm,
        }))
    }
}

/// One region's loads at `time_s` (the topic's predictor) into the outputs through `scratch`;
/// false (outputs untouched) with nothing published.
fn read_loads(
    data: &DataManager,
    channel: &LoadsChannel,
    scratch: &mut PublishedLoads,
    time_s: f64,
    total: &mut Loads,
    aero: Option<&mut Loads>,
    generalized: &mut [f64],
) -> Result<bool, DataError> {
    match data.read_at(channel.reader, time_s, scratch) {
        Err(DataError::NothingConverged { .. }) => return Ok(false),
        Err(e) => return Err(e),
        Ok(_) => {}
    }
    copy_loads(scratch, (channel, time_s), total, aero, generalized)?;
    Ok(true)
}

/// A region's latest publication (an iterate or converged) into the outputs, as [`read_loads`]
/// but without the predictor: what the region gave at this very evaluation.
fn read_latest_loads(
    data: &DataManager,
    channel: &LoadsChannel,
    total: &mut Loads,
    aero: Option<&mut Loads>,
    generalized: &mut [f64],
) -> Result<(), DataError> {
    let latest = data.read(channel.reader)?;
    copy_loads(
        latest.value,
        (channel, latest.time_s),
        total,
        aero,
        generalized,
    )
}

/// A publication of `channel`'s topic (read at `time_s`) into the outputs. Generalized forces of
/// another length than `generalized` are refused naming the topic: publisher and reader were
/// wired to different mode counts, a defect no later read would repair.
fn copy_loads(
    value: &PublishedLoads,
    (channel, time_s): (&LoadsChannel, f64),
    total: &mut Loads,
    aero: Option<&mut Loads>,
    generalized: &mut [f64],
) -> Result<(), DataError> {
    if value.generalized.len() != generalized.len() {
        return Err(DataError::LengthMismatch {
            topic: channel.topic.clone(),
            reader: READER.to_owned(),
            time_s,
            published: value.generalized.len(),
            expected: generalized.len(),
        });
    }
    total.force_n = value.force_n;
    total.moment_nm = value.moment_nm;
    if let Some(aero) = aero {
        aero.force_n = value.aero_force_n;
        aero.moment_nm = value.aero_moment_nm;
    }
    generalized.copy_from_slice(value.generalized.as_slice());
    Ok(())
}

/// Publishes one region's loads at `time_s`, in place (the head's buffers reused); a
/// converged publication is committed into the history the predictor reads.
fn publish_loads(
    data: &mut DataManager,
    publisher: Publisher<PublishedLoads>,
    (time_s, publication): (f64, Publication),
    total: &Loads,
    aero: &Loads,
    generalized: &[f64],
) -> Result<(), DataError> {
    data.publish_with(publisher, time_s, |slot| {
        slot.force_n = total.force_n;
        slot.moment_nm = total.moment_nm;
        slot.aero_force_n = aero.force_n;
        slot.aero_moment_nm = aero.moment_nm;
        if slot.generalized.len() == generalized.len() {
            slot.generalized.copy_from_slice(generalized);
        } else {
            slot.generalized = DVector::from_column_slice(generalized);
        }
    })?;
    if publication == Publication::Converged {
        data.mark_converged(publisher)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests;
