//! The exchange store regions talk through (the paper, §III): typed topics holding the latest
//! iterate, a ring of converged stamped values read at any time, and checkpoints of it all.
//!
//! Regions never call each other. At assembly each region declares the topics it publishes and
//! the topics it subscribes to; the builder resolves every name once into a typed handle and
//! fails if a subscribed topic has no publisher, if two regions publish the same topic, if
//! publisher and subscriber disagree on the value type, or if a declared rate or history is
//! unusable. In the time loop a handle is an index: no string look-up.
//!
//! # Iterates and converged values
//! Within a coupled step regions publish *iterates* (fixed-point iteration): each publication
//! replaces the topic's head and is what [`DataManager::read`] returns, stamped
//! `converged: false`. Only [`DataManager::mark_converged`] (one topic) or
//! [`DataManager::commit`] (every topic) copies the head into the topic's history, a ring of
//! stamped converged values; [`DataManager::read_at`] reads that history only, interpolated
//! linearly between the two values bracketing the asked time (topics declared with
//! [`DataManagerBuilder::publish_interpolated`]) or held from the earlier one (all other topics),
//! and held from the newest value beyond it (zero-order hold, no extrapolation).
//!
//! # Rates and history, checked by [`DataManagerBuilder::build`]
//! 1. Every period a publisher or subscriber declares is finite and > 0 s; a history is finite
//!    and ≥ 0 s.
//! 2. A publisher's period is the shortest interval between two converged values; committing
//!    sooner (relative tolerance [`PERIOD_TOLERANCE`]) is refused. Committing again at the time
//!    of the newest converged value replaces it (a step re-converged, e.g. trim at t = 0).
//! 3. Reader and publisher periods may stand in any ratio: a reader faster than its publisher
//!    interpolates or holds between publications (the canonical 10 ms publisher, 1 ms reader);
//!    a slower reader finds every value of its last step in the ring.
//! 4. A subscriber that declares a period reads history, so its publisher must declare one too
//!    (otherwise the ring cannot be sized).
//! 5. The ring keeps, for the most demanding subscriber,
//!    `⌈(history_s + reader period_s) / publisher period_s⌉ + 2` values: everything committed in
//!    the declared history plus one reader step (the reader may lag the publisher by one of its
//!    own steps), one older value to bracket the oldest time and one for rounding of the
//!    publication times. At least [`MIN_HISTORY_SAMPLES`], at most [`MAX_HISTORY_SAMPLES`]
//!    (more is refused at assembly).
//!
//! # No allocation in the time loop
//! [`DataManager::publish_with`] updates the head in place; a commit copies the head into the
//! ring's next slot, which after the ring has filled once is an old value overwritten in place
//! (`Clone::clone_from`, or [`Interpolate::copy_into`] for interpolated topics so
//! `nalgebra::DVector` reuses its storage too); [`DataManager::read_at`] writes into the caller's
//! buffer. [`DataManager::checkpoint_into`] and [`DataManager::restore`] from an in-memory
//! checkpoint reuse the buffers they already hold.
//!
//! # Checkpoints
//! [`DataCheckpoint`] is plain data (Clone, serde) holding every topic's head, ring and version.
//! Restoring returns the manager to a bit-identical state. In a serialized checkpoint every
//! `f64` is written as `{"$f64": "<shortest round-trip decimal>"}`, so restart files are
//! bit-exact whatever float parser reads them; non-finite values cannot be written to a file.

use std::any::{Any, TypeId, type_name};
use std::fmt;
use std::marker::PhantomData;

use nalgebra::{DMatrix, DVector, SMatrix};
use serde::de::{DeserializeOwned, Error as _};
use serde::ser::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::{Number, Value};

/// What a topic may carry: plain data that can be cloned, sent between threads and written to a
/// restart file.
pub trait TopicValue: Clone + Serialize + DeserializeOwned + Send + Sync + 'static {}
impl<T: Clone + Serialize + DeserializeOwned + Send + Sync + 'static> TopicValue for T {}

/// Fewest converged values a topic keeps: two, so a read between the last two commits works.
pub const MIN_HISTORY_SAMPLES: usize = 2;
/// Most converged values a topic may keep (e.g. 65 s of a 1 ms publisher).
pub const MAX_HISTORY_SAMPLES: usize = 65_536;
/// Relative slack on a publisher's period when checking the spacing of commits, so times built
/// by repeated addition (`t += dt`) pass.
pub const PERIOD_TOLERANCE: f64 = 1e-6;
/// Format number of serialized checkpoints.
const CHECKPOINT_FORMAT: u32 = 1;
/// Key of the object a serialized checkpoint writes each `f64` as.
const FLOAT_TAG: &str = "$f64";

/// Why assembling, publishing, reading or restoring the data manager failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DataError {
    #[error(
        "topic `{topic}` is subscribed to by {subscribers} but no region publishes it; publishers exist for: {known}"
    )]
    NoPublisher {
        topic: String,
        subscribers: String,
        known: String,
    },
    #[error(
        "topic `{topic}` is published by both `{first}` and `{second}`; a topic has one publisher"
    )]
    DuplicatePublisher {
        topic: String,
        first: String,
        second: String,
    },
    #[error(
        "topic `{topic}` is declared as `{first}` by `{first_region}` but as `{second}` by `{second_region}`"
    )]
    TypeMismatch {
        topic: String,
        first: &'static str,
        first_region: String,
        second: &'static str,
        second_region: String,
    },
    #[error(
        "topic `{topic}`: {role} `{region}` declares {quantity} = {value}; it must be {allowed}"
    )]
    InvalidRate {
        topic: String,
        role: &'static str,
        region: String,
        quantity: &'static str,
        value: f64,
        allowed: &'static str,
    },
    #[error(
        "topic `{topic}`: subscriber `{subscriber}` reads every {reader_period_s} s with {history_s} s of history, but publisher `{publisher}` declares no period; declare one (publish_with_rate or publish_interpolated) so the history can be sized"
    )]
    UnratedPublisher {
        topic: String,
        publisher: String,
        subscriber: String,
        reader_period_s: f64,
        history_s: f64,
    },
    #[error(
        "topic `{topic}`: subscriber `{subscriber}` (period {reader_period_s} s, history {history_s} s) of publisher `{publisher}` (period {publisher_period_s} s) needs {samples} stored values; at most {max} are kept"
    )]
    HistoryTooLong {
        topic: String,
        publisher: String,
        subscriber: String,
        reader_period_s: f64,
        history_s: f64,
        publisher_period_s: f64,
        samples: u64,
        max: usize,
    },
    #[error("topic `{topic}` was read by `{reader}` before anything was published to it")]
    NotYetPublished { topic: String, reader: String },
    #[error(
        "topic `{topic}`: `{reader}` read its converged history before any value was committed"
    )]
    NothingConverged { topic: String, reader: String },
    #[error("topic `{topic}`: `{region}` used the non-finite time {time_s} s")]
    NonFiniteTime {
        topic: String,
        region: String,
        time_s: f64,
    },
    #[error("commit asked for up to the non-finite time {time_s} s")]
    NonFiniteCommitTime { time_s: f64 },
    #[error(
        "topic `{topic}`: `{publisher}` published at t = {time_s} s, before its newest converged value at t = {newest_s} s"
    )]
    PublishedBeforeHistory {
        topic: String,
        publisher: String,
        time_s: f64,
        newest_s: f64,
    },
    #[error(
        "topic `{topic}`: `{publisher}` committed a value at t = {time_s} s, {gap_s} s after the previous one at t = {previous_s} s, but declares a period of {period_s} s"
    )]
    CommitTooSoon {
        topic: String,
        publisher: String,
        time_s: f64,
        previous_s: f64,
        gap_s: f64,
        period_s: f64,
    },
    #[error(
        "topic `{topic}`: `{reader}` read t = {time_s} s, older than the oldest value kept (t = {oldest_s} s); declare the history it needs with subscribe_with"
    )]
    ReadBeforeHistory {
        topic: String,
        reader: String,
        time_s: f64,
        oldest_s: f64,
    },
    #[error(
        "topic `{topic}`: `{reader}` read t = {time_s} s between values of shape {earlier:?} and {later:?}, which cannot be interpolated"
    )]
    ShapeChanged {
        topic: String,
        reader: String,
        time_s: f64,
        earlier: (usize, usize),
        later: (usize, usize),
    },
    #[error("a handle for `{type_name}` (slot {slot}) was not issued for this data manager")]
    ForeignHandle {
        type_name: &'static str,
        slot: usize,
    },
    #[error(
        "checkpoint holds topics [{found}] but this data manager has [{expected}]; a checkpoint restores only the topic table it was taken from"
    )]
    CheckpointTopics { expected: String, found: String },
    #[error("checkpoint of topic `{topic}` cannot be restored: {reason}")]
    CheckpointState { topic: String, reason: String },
}

/// How [`DataManager::read_at`] fills the time between two converged values of a topic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Interpolation {
    /// `x(t) = x₀ + (t − t₀)/(t₁ − t₀) (x₁ − x₀)`: exact on signals linear in time.
    Linear,
    /// `x(t) = x₀`, the newest value at or before `t` (zero-order hold): any value type.
    Hold,
}

/// What a subscriber needs from a topic's history: the period it reads at (s) and how far back
/// beyond its own step it reads (s; e.g. the span of a convolution).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SubscriptionSpec {
    pub period_s: f64,
    pub history_s: f64,
}

impl SubscriptionSpec {
    /// Reads every `period_s` seconds, only within its last step.
    pub fn every(period_s: f64) -> Self {
        Self {
            period_s,
            history_s: 0.0,
        }
    }

    /// Also reads `history_s` seconds further back.
    pub fn with_history(self, history_s: f64) -> Self {
        Self { history_s, ..self }
    }
}

/// Shapes, as (rows, columns), of two values that cannot be interpolated into each other.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShapeMismatch {
    pub earlier: (usize, usize),
    pub later: (usize, usize),
}

/// Values that can be read between two converged samples by linear interpolation.
pub trait Interpolate: Clone {
    /// `out = self + w (other − self)` with `w` ∈ [0, 1] the weight of `other`; reuses `out`.
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch>;

    /// `out = self`, reusing the storage `out` already owns.
    fn copy_into(&self, out: &mut Self) {
        out.clone_from(self);
    }
}

/// `a + w (b − a)`.
fn lerp(a: f64, b: f64, w: f64) -> f64 {
    a + w * (b - a)
}

impl Interpolate for f64 {
    fn lerp_into(&self, other: &f64, w: f64, out: &mut f64) -> Result<(), ShapeMismatch> {
        *out = lerp(*self, *other, w);
        Ok(())
    }
}

impl<T: Interpolate, const N: usize> Interpolate for [T; N] {
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        for ((o, a), b) in out.iter_mut().zip(self).zip(other) {
            a.lerp_into(b, w, o)?;
        }
        Ok(())
    }

    fn copy_into(&self, out: &mut Self) {
        for (o, a) in out.iter_mut().zip(self) {
            a.copy_into(o);
        }
    }
}

impl<T: Interpolate> Interpolate for Vec<T> {
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        if self.len() != other.len() {
            return Err(ShapeMismatch {
                earlier: (self.len(), 1),
                later: (other.len(), 1),
            });
        }
        self.copy_into(out);
        for ((o, a), b) in out.iter_mut().zip(self).zip(other) {
            a.lerp_into(b, w, o)?;
        }
        Ok(())
    }

    fn copy_into(&self, out: &mut Self) {
        out.truncate(self.len());
        let kept = out.len();
        for (o, a) in out.iter_mut().zip(self) {
            a.copy_into(o);
        }
        out.extend_from_slice(&self[kept..]);
    }
}

impl<const R: usize, const C: usize> Interpolate for SMatrix<f64, R, C> {
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        for ((o, a), b) in out.iter_mut().zip(self.iter()).zip(other.iter()) {
            *o = lerp(*a, *b, w);
        }
        Ok(())
    }
}

/// Interpolation for heap-backed nalgebra matrices: shapes must agree, `out` is reused.
macro_rules! interpolate_dynamic_matrix {
    ($matrix:ty) => {
        impl Interpolate for $matrix {
            fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
                if self.shape() != other.shape() {
                    return Err(ShapeMismatch {
                        earlier: self.shape(),
                        later: other.shape(),
                    });
                }
                self.copy_into(out);
                for ((o, a), b) in out.iter_mut().zip(self.iter()).zip(other.iter()) {
                    *o = lerp(*a, *b, w);
                }
                Ok(())
            }

            fn copy_into(&self, out: &mut Self) {
                if out.shape() == self.shape() {
                    out.copy_from(self);
                } else {
                    *out = self.clone();
                }
            }
        }
    };
}
interpolate_dynamic_matrix!(DVector<f64>);
interpolate_dynamic_matrix!(DMatrix<f64>);

/// Handle that lets one region publish values of type `T` on one topic.
pub struct Publisher<T> {
    slot: usize,
    _value: PhantomData<fn(T)>,
}

/// Handle that lets one region read values of type `T` from one topic.
pub struct Subscriber<T> {
    slot: usize,
    reader: usize,
    _value: PhantomData<fn() -> T>,
}

impl<T> Clone for Publisher<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Publisher<T> {}
impl<T> Clone for Subscriber<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Subscriber<T> {}

impl<T> fmt::Debug for Publisher<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Publisher<{}>(slot {})", type_name::<T>(), self.slot)
    }
}
impl<T> fmt::Debug for Subscriber<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Subscriber<{}>(slot {})", type_name::<T>(), self.slot)
    }
}

/// A value as read from the data manager: the value, the simulation time it holds at (s), a
/// version that increases by one on every publication of the topic, and whether it is a
/// converged value (in the history) or an iterate of the current step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stamped<'a, T> {
    pub value: &'a T,
    pub time_s: f64,
    pub version: u64,
    pub converged: bool,
}

/// The converged values a [`DataManager::read_at`] used:
/// `value = earlier + weight (later − earlier)`; `earlier == later` and `weight = 0` when one
/// value was copied (exact time, hold, or beyond the newest value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bracket {
    pub earlier_time_s: f64,
    pub earlier_version: u64,
    pub later_time_s: f64,
    pub later_version: u64,
    pub weight: f64,
}

/// A topic as assembled: its name, publisher, value type, declared period (s), interpolation
/// and the number of converged values its ring keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopicInfo<'a> {
    pub name: &'a str,
    pub publisher: &'a str,
    pub type_name: &'static str,
    pub period_s: Option<f64>,
    pub interpolation: Interpolation,
    pub history_depth: usize,
}

// ---------------------------------------------------------------------------------------------
// Assembly
// ---------------------------------------------------------------------------------------------

/// Builds the type-erased store of one topic with a ring of the given depth.
type MakeTopic = fn(usize) -> Box<dyn ErasedTopic>;

struct PublisherDeclaration {
    region: String,
    period_s: Option<f64>,
    interpolation: Interpolation,
    make: MakeTopic,
}

struct SubscriberDeclaration {
    region: String,
    spec: Option<SubscriptionSpec>,
}

struct TopicDeclaration {
    name: String,
    type_id: TypeId,
    type_name: &'static str,
    declared_by: String,
    publisher: Option<PublisherDeclaration>,
    subscribers: Vec<SubscriberDeclaration>,
}

/// Collects the topic declarations of every region before the run starts.
#[derive(Default)]
pub struct DataManagerBuilder {
    topics: Vec<TopicDeclaration>,
    readers: Vec<String>,
}

impl DataManagerBuilder {
    pub fn new() -> Self {
        Self::default()
    }

    fn declare<T: Any>(&mut self, region: &str, topic: &str) -> Result<usize, DataError> {
        if let Some(index) = self.topics.iter().position(|t| t.name == topic) {
            let declared = &self.topics[index];
            if declared.type_id != TypeId::of::<T>() {
                return Err(DataError::TypeMismatch {
                    topic: topic.to_owned(),
                    first: declared.type_name,
                    first_region: declared.declared_by.clone(),
                    second: type_name::<T>(),
                    second_region: region.to_owned(),
                });
            }
            return Ok(index);
        }
        self.topics.push(TopicDeclaration {
            name: topic.to_owned(),
            type_id: TypeId::of::<T>(),
            type_name: type_name::<T>(),
            declared_by: region.to_owned(),
            publisher: None,
            subscribers: Vec::new(),
        });
        Ok(self.topics.len() - 1)
    }

    fn declare_publisher<T: TopicValue>(
        &mut self,
        region: &str,
        topic: &str,
        period_s: Option<f64>,
        interpolation: Interpolation,
        make: MakeTopic,
    ) -> Result<Publisher<T>, DataError> {
        let slot = self.declare::<T>(region, topic)?;
        let declaration = &mut self.topics[slot];
        if let Some(first) = &declaration.publisher {
            return Err(DataError::DuplicatePublisher {
                topic: topic.to_owned(),
                first: first.region.clone(),
                second: region.to_owned(),
            });
        }
        declaration.publisher = Some(PublisherDeclaration {
            region: region.to_owned(),
            period_s,
            interpolation,
            make,
        });
        Ok(Publisher {
            slot,
            _value: PhantomData,
        })
    }

    /// Declares that `region` publishes `topic` whenever it likes; reads between values hold.
    /// A topic has exactly one publisher.
    pub fn publish<T: TopicValue>(
        &mut self,
        region: &str,
        topic: &str,
    ) -> Result<Publisher<T>, DataError> {
        self.declare_publisher(region, topic, None, Interpolation::Hold, hold_topic::<T>)
    }

    /// Declares that `region` commits `topic` at most every `period_s` seconds; reads between
    /// values hold the earlier one (any value type).
    pub fn publish_with_rate<T: TopicValue>(
        &mut self,
        region: &str,
        topic: &str,
        period_s: f64,
    ) -> Result<Publisher<T>, DataError> {
        let make = hold_topic::<T>;
        self.declare_publisher(region, topic, Some(period_s), Interpolation::Hold, make)
    }

    /// Declares that `region` commits `topic` at most every `period_s` seconds; reads between
    /// values interpolate linearly.
    pub fn publish_interpolated<T: TopicValue + Interpolate>(
        &mut self,
        region: &str,
        topic: &str,
        period_s: f64,
    ) -> Result<Publisher<T>, DataError> {
        let make = linear_topic::<T>;
        self.declare_publisher(region, topic, Some(period_s), Interpolation::Linear, make)
    }

    fn declare_subscriber<T: TopicValue>(
        &mut self,
        region: &str,
        topic: &str,
        spec: Option<SubscriptionSpec>,
    ) -> Result<Subscriber<T>, DataError> {
        let slot = self.declare::<T>(region, topic)?;
        self.topics[slot].subscribers.push(SubscriberDeclaration {
            region: region.to_owned(),
            spec,
        });
        self.readers.push(region.to_owned());
        Ok(Subscriber {
            slot,
            reader: self.readers.len() - 1,
            _value: PhantomData,
        })
    }

    /// Declares that `region` reads `topic` without a declared rate (the latest value, and the
    /// history as far as other subscribers keep it); checked in [`Self::build`].
    pub fn subscribe<T: TopicValue>(
        &mut self,
        region: &str,
        topic: &str,
    ) -> Result<Subscriber<T>, DataError> {
        self.declare_subscriber(region, topic, None)
    }

    /// Declares that `region` reads `topic` every `spec.period_s` seconds and `spec.history_s`
    /// seconds back; the topic's ring is sized for it in [`Self::build`].
    pub fn subscribe_with<T: TopicValue>(
        &mut self,
        region: &str,
        topic: &str,
        spec: SubscriptionSpec,
    ) -> Result<Subscriber<T>, DataError> {
        self.declare_subscriber(region, topic, Some(spec))
    }

    /// Checks publishers, rates and histories (module docs, rules 1–5) and freezes the table.
    pub fn build(self) -> Result<DataManager, DataError> {
        self.check_every_topic_published()?;
        let slots = self
            .topics
            .into_iter()
            .map(TopicDeclaration::into_slot)
            .collect::<Result<Vec<_>, _>>()?;
        Ok(DataManager {
            slots,
            readers: self.readers,
        })
    }

    fn check_every_topic_published(&self) -> Result<(), DataError> {
        let Some(orphan) = self.topics.iter().find(|t| t.publisher.is_none()) else {
            return Ok(());
        };
        let known: Vec<&str> = self
            .topics
            .iter()
            .filter(|t| t.publisher.is_some())
            .map(|t| t.name.as_str())
            .collect();
        Err(DataError::NoPublisher {
            topic: orphan.name.clone(),
            subscribers: orphan.subscriber_names(),
            known: if known.is_empty() {
                "(none)".to_owned()
            } else {
                known.join(", ")
            },
        })
    }
}

impl TopicDeclaration {
    fn subscriber_names(&self) -> String {
        let names: Vec<&str> = self.subscribers.iter().map(|s| s.region.as_str()).collect();
        names.join(", ")
    }

    fn into_slot(self) -> Result<Slot, DataError> {
        let Some(publisher) = &self.publisher else {
            return Err(DataError::NoPublisher {
                topic: self.name.clone(),
                subscribers: self.subscriber_names(),
                known: String::new(),
            });
        };
        if let Some(period_s) = publisher.period_s {
            check_period(&self.name, "publisher", &publisher.region, period_s)?;
        }
        let mut depth = MIN_HISTORY_SAMPLES;
        for subscriber in &self.subscribers {
            if let Some(spec) = subscriber.spec {
                depth = depth.max(self.depth_for(publisher, &subscriber.region, spec)?);
            }
        }
        let meta = TopicMeta {
            name: self.name,
            publisher: publisher.region.clone(),
            type_name: self.type_name,
            period_s: publisher.period_s,
            interpolation: publisher.interpolation,
            history_depth: depth,
        };
        Ok(Slot {
            meta,
            topic: (publisher.make)(depth),
        })
    }

    /// Ring depth one subscriber needs (module docs, rules 4 and 5).
    fn depth_for(
        &self,
        publisher: &PublisherDeclaration,
        subscriber: &str,
        spec: SubscriptionSpec,
    ) -> Result<usize, DataError> {
        check_period(&self.name, "subscriber", subscriber, spec.period_s)?;
        check_history(&self.name, subscriber, spec.history_s)?;
        let Some(publisher_period_s) = publisher.period_s else {
            return Err(DataError::UnratedPublisher {
                topic: self.name.clone(),
                publisher: publisher.region.clone(),
                subscriber: subscriber.to_owned(),
                reader_period_s: spec.period_s,
                history_s: spec.history_s,
            });
        };
        let samples = samples_needed(spec.history_s, spec.period_s, publisher_period_s);
        if samples > MAX_HISTORY_SAMPLES as f64 {
            return Err(DataError::HistoryTooLong {
                topic: self.name.clone(),
                publisher: publisher.region.clone(),
                subscriber: subscriber.to_owned(),
                reader_period_s: spec.period_s,
                history_s: spec.history_s,
                publisher_period_s,
                samples: samples as u64,
                max: MAX_HISTORY_SAMPLES,
            });
        }
        Ok(samples as usize)
    }
}

/// `⌈(history + reader period) / publisher period⌉ + 2` stored values (module docs, rule 5); the
/// 1e-9 keeps an exact ratio such as 0.01 / 0.001 from rounding up a whole sample.
fn samples_needed(history_s: f64, reader_period_s: f64, publisher_period_s: f64) -> f64 {
    ((history_s + reader_period_s) / publisher_period_s - 1e-9).ceil() + 2.0
}

/// A period (s) must be finite and > 0.
fn check_period(
    topic: &str,
    role: &'static str,
    region: &str,
    value: f64,
) -> Result<(), DataError> {
    if value.is_finite() && value > 0.0 {
        return Ok(());
    }
    Err(DataError::InvalidRate {
        topic: topic.to_owned(),
        role,
        region: region.to_owned(),
        quantity: "period_s",
        value,
        allowed: "finite and > 0 s",
    })
}

/// A history span (s) must be finite and ≥ 0.
fn check_history(topic: &str, region: &str, value: f64) -> Result<(), DataError> {
    if value.is_finite() && value >= 0.0 {
        return Ok(());
    }
    Err(DataError::InvalidRate {
        topic: topic.to_owned(),
        role: "subscriber",
        region: region.to_owned(),
        quantity: "history_s",
        value,
        allowed: "finite and ≥ 0 s",
    })
}

fn hold_topic<T: TopicValue>(depth: usize) -> Box<dyn ErasedTopic> {
    Box::new(Topic::<T>::new(depth, clone_into::<T>, None))
}

fn linear_topic<T: TopicValue + Interpolate>(depth: usize) -> Box<dyn ErasedTopic> {
    Box::new(Topic::<T>::new(depth, T::copy_into, Some(T::lerp_into)))
}

fn clone_into<T: Clone>(value: &T, out: &mut T) {
    out.clone_from(value);
}

// ---------------------------------------------------------------------------------------------
// Per-topic state
// ---------------------------------------------------------------------------------------------

/// One stamped value: simulation time (s), publication count, value.
#[derive(Debug, Serialize, Deserialize)]
struct Sample<T> {
    time_s: f64,
    version: u64,
    value: T,
}

impl<T: Clone> Clone for Sample<T> {
    fn clone(&self) -> Self {
        Self {
            time_s: self.time_s,
            version: self.version,
            value: self.value.clone(),
        }
    }
}

impl<T> Sample<T> {
    fn copy_from(&mut self, source: &Self, copy: CopyFn<T>) {
        self.time_s = source.time_s;
        self.version = source.version;
        copy(&source.value, &mut self.value);
    }

    fn stamped(&self, converged: bool) -> Stamped<'_, T> {
        Stamped {
            value: &self.value,
            time_s: self.time_s,
            version: self.version,
            converged,
        }
    }

    fn alone(&self) -> Bracket {
        Bracket {
            earlier_time_s: self.time_s,
            earlier_version: self.version,
            later_time_s: self.time_s,
            later_version: self.version,
            weight: 0.0,
        }
    }
}

/// The newest publication of a topic, an iterate until committed.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Head<T> {
    sample: Sample<T>,
    converged: bool,
}

/// Everything a checkpoint of one topic holds: the head and the ring of converged values,
/// `history[oldest]` the oldest, in time order from there, wrapping around.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct TopicState<T> {
    head: Option<Head<T>>,
    history: Vec<Sample<T>>,
    oldest: usize,
}

type CopyFn<T> = fn(&T, &mut T);
type LerpFn<T> = fn(&T, &T, f64, &mut T) -> Result<(), ShapeMismatch>;

impl<T: Clone> TopicState<T> {
    fn version(&self) -> u64 {
        self.head.as_ref().map_or(0, |h| h.sample.version)
    }

    /// The `rank`-th oldest converged value.
    fn at(&self, rank: usize) -> &Sample<T> {
        &self.history[(self.oldest + rank) % self.history.len()]
    }

    fn newest(&self) -> Option<&Sample<T>> {
        self.history.len().checked_sub(1).map(|last| self.at(last))
    }

    /// Number of converged values stamped at or before `time_s` (binary search on the ring).
    fn count_at_or_before(&self, time_s: f64) -> usize {
        let (mut low, mut high) = (0, self.history.len());
        while low < high {
            let mid = low + (high - low) / 2;
            if self.at(mid).time_s <= time_s {
                low = mid + 1;
            } else {
                high = mid;
            }
        }
        low
    }

    /// Replaces the head with a new iterate.
    fn set_head(&mut self, time_s: f64, value: T) -> u64 {
        let version = self.version() + 1;
        let sample = Sample {
            time_s,
            version,
            value,
        };
        match &mut self.head {
            Some(head) => {
                head.sample = sample;
                head.converged = false;
            }
            None => {
                self.head = Some(Head {
                    sample,
                    converged: false,
                })
            }
        }
        version
    }

    /// Updates the head in place (from `T::default()` the first time) as a new iterate.
    fn update_head(&mut self, time_s: f64, update: impl FnOnce(&mut T)) -> u64
    where
        T: Default,
    {
        let version = self.version() + 1;
        let head = self.head.get_or_insert_with(|| Head {
            sample: Sample {
                time_s,
                version,
                value: T::default(),
            },
            converged: false,
        });
        update(&mut head.sample.value);
        head.sample.time_s = time_s;
        head.sample.version = version;
        head.converged = false;
        version
    }

    /// `self = source`, reusing the values already held.
    fn copy_from(&mut self, source: &Self, copy: CopyFn<T>) {
        match (&mut self.head, &source.head) {
            (Some(head), Some(from)) => {
                head.sample.copy_from(&from.sample, copy);
                head.converged = from.converged;
            }
            (head, from) => head.clone_from(from),
        }
        self.history.truncate(source.history.len());
        let kept = self.history.len();
        for (sample, from) in self.history.iter_mut().zip(&source.history) {
            sample.copy_from(from, copy);
        }
        self.history.extend_from_slice(&source.history[kept..]);
        self.oldest = source.oldest;
    }

    /// The ring invariants a restored state must meet for a ring of `depth` values.
    fn check_ring(&self, depth: usize) -> Result<(), String> {
        let len = self.history.len();
        if len > depth {
            return Err(format!(
                "its history holds {len} values, more than the {depth} this topic keeps"
            ));
        }
        let oldest_valid = if len == 0 {
            self.oldest == 0
        } else {
            self.oldest < len && (self.oldest == 0 || len == depth)
        };
        if !oldest_valid {
            return Err(format!(
                "ring index {} does not fit a history of {len} values kept in {depth}",
                self.oldest
            ));
        }
        let times_increase = (1..len).all(|rank| self.at(rank - 1).time_s < self.at(rank).time_s);
        let times_finite = (0..len).all(|rank| self.at(rank).time_s.is_finite());
        if !(times_increase && times_finite) {
            return Err("its history times are not finite and increasing".to_owned());
        }
        Ok(())
    }
}

/// Why a typed read of the history found no value.
enum Miss {
    Empty,
    TooOld { oldest_s: f64 },
    Shape(ShapeMismatch),
}

/// The store of one topic: its state plus how values of `T` are copied and interpolated.
struct Topic<T> {
    state: TopicState<T>,
    depth: usize,
    copy: CopyFn<T>,
    lerp: Option<LerpFn<T>>,
}

impl<T: TopicValue> Topic<T> {
    fn new(depth: usize, copy: CopyFn<T>, lerp: Option<LerpFn<T>>) -> Self {
        Self {
            state: TopicState {
                head: None,
                history: Vec::with_capacity(depth),
                oldest: 0,
            },
            depth,
            copy,
            lerp,
        }
    }

    /// The converged value at `time_s` into `out`: interpolated or held between the bracketing
    /// values, held from the newest beyond it.
    fn sample_at(&self, time_s: f64, out: &mut T) -> Result<Bracket, Miss> {
        let state = &self.state;
        let len = state.history.len();
        if len == 0 {
            return Err(Miss::Empty);
        }
        let count = state.count_at_or_before(time_s);
        if count == 0 {
            let oldest_s = state.at(0).time_s;
            return Err(Miss::TooOld { oldest_s });
        }
        let earlier = state.at(count - 1);
        let lerp = match self.lerp {
            Some(lerp) if count < len && earlier.time_s != time_s => lerp,
            _ => {
                (self.copy)(&earlier.value, out);
                return Ok(earlier.alone());
            }
        };
        let later = state.at(count);
        let weight = (time_s - earlier.time_s) / (later.time_s - earlier.time_s);
        lerp(&earlier.value, &later.value, weight, out).map_err(Miss::Shape)?;
        Ok(Bracket {
            earlier_time_s: earlier.time_s,
            earlier_version: earlier.version,
            later_time_s: later.time_s,
            later_version: later.version,
            weight,
        })
    }
}

/// The operations the manager needs on a topic without knowing its value type.
trait ErasedTopic: Any + Send + Sync {
    /// Time (s) of the head if it is an uncommitted iterate.
    fn pending_time(&self) -> Option<f64>;
    /// Time (s) of the newest converged value.
    fn newest_time(&self) -> Option<f64>;
    /// Copies a pending head into the ring; false if nothing was pending.
    fn commit_head(&mut self) -> bool;
    fn snapshot(&self) -> Box<dyn ErasedState>;
    /// Copies the state into a snapshot of the same type; false if the type differs.
    fn snapshot_into(&self, into: &mut dyn ErasedState) -> bool;
    fn parse_state(&self, value: &Value) -> Result<Box<dyn ErasedState>, String>;
    fn check_state(&self, state: &dyn ErasedState) -> Result<(), String>;
    /// Restores a state that passed [`ErasedTopic::check_state`].
    fn restore(&mut self, state: &dyn ErasedState);
}

/// A snapshot of one topic's state without its value type.
trait ErasedState: Any + Send + Sync {
    fn clone_state(&self) -> Box<dyn ErasedState>;
    fn to_value(&self) -> Result<Value, serde_json::Error>;
}

impl<T: TopicValue> ErasedState for TopicState<T> {
    fn clone_state(&self) -> Box<dyn ErasedState> {
        Box::new(self.clone())
    }

    fn to_value(&self) -> Result<Value, serde_json::Error> {
        serde_json::to_value(self)
    }
}

impl<T: TopicValue> ErasedTopic for Topic<T> {
    fn pending_time(&self) -> Option<f64> {
        let head = self.state.head.as_ref()?;
        (!head.converged).then_some(head.sample.time_s)
    }

    fn newest_time(&self) -> Option<f64> {
        self.state.newest().map(|s| s.time_s)
    }

    fn commit_head(&mut self) -> bool {
        let newest_time = self.newest_time();
        let TopicState {
            head,
            history,
            oldest,
        } = &mut self.state;
        let Some(head) = head.as_mut().filter(|h| !h.converged) else {
            return false;
        };
        let len = history.len();
        if newest_time == Some(head.sample.time_s) {
            history[(*oldest + len - 1) % len].copy_from(&head.sample, self.copy);
        } else if len < self.depth {
            history.push(head.sample.clone());
        } else {
            history[*oldest].copy_from(&head.sample, self.copy);
            *oldest = (*oldest + 1) % len;
        }
        head.converged = true;
        true
    }

    fn snapshot(&self) -> Box<dyn ErasedState> {
        Box::new(self.state.clone())
    }

    fn snapshot_into(&self, into: &mut dyn ErasedState) -> bool {
        let into: &mut dyn Any = into;
        match into.downcast_mut::<TopicState<T>>() {
            Some(state) => {
                state.copy_from(&self.state, self.copy);
                true
            }
            None => false,
        }
    }

    fn parse_state(&self, value: &Value) -> Result<Box<dyn ErasedState>, String> {
        match TopicState::<T>::deserialize(value) {
            Ok(state) => Ok(Box::new(state)),
            Err(e) => Err(format!("not a `{}` topic state: {e}", type_name::<T>())),
        }
    }

    fn check_state(&self, state: &dyn ErasedState) -> Result<(), String> {
        let state: &dyn Any = state;
        match state.downcast_ref::<TopicState<T>>() {
            Some(state) => state.check_ring(self.depth),
            None => Err(format!(
                "it holds another value type than `{}`",
                type_name::<T>()
            )),
        }
    }

    fn restore(&mut self, state: &dyn ErasedState) {
        let state: &dyn Any = state;
        if let Some(state) = state.downcast_ref::<TopicState<T>>() {
            self.state.copy_from(state, self.copy);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The manager
// ---------------------------------------------------------------------------------------------

struct TopicMeta {
    name: String,
    publisher: String,
    type_name: &'static str,
    period_s: Option<f64>,
    interpolation: Interpolation,
    history_depth: usize,
}

struct Slot {
    meta: TopicMeta,
    topic: Box<dyn ErasedTopic>,
}

/// The central store: per topic the latest publication (iterate or converged) and a ring of
/// converged stamped values.
pub struct DataManager {
    slots: Vec<Slot>,
    readers: Vec<String>,
}

impl fmt::Debug for DataManager {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.topics()).finish()
    }
}

/// A publication at `time_s` must be finite and not older than the newest converged value.
fn check_publication(
    meta: &TopicMeta,
    newest_s: Option<f64>,
    time_s: f64,
) -> Result<(), DataError> {
    if !time_s.is_finite() {
        return Err(DataError::NonFiniteTime {
            topic: meta.name.clone(),
            region: meta.publisher.clone(),
            time_s,
        });
    }
    match newest_s {
        Some(newest_s) if time_s < newest_s => Err(DataError::PublishedBeforeHistory {
            topic: meta.name.clone(),
            publisher: meta.publisher.clone(),
            time_s,
            newest_s,
        }),
        _ => Ok(()),
    }
}

/// A commit at `time_s` replaces the newest converged value at the same time or comes at least
/// one declared period (less [`PERIOD_TOLERANCE`]) after it.
fn check_commit(meta: &TopicMeta, newest_s: Option<f64>, time_s: f64) -> Result<(), DataError> {
    check_publication(meta, newest_s, time_s)?;
    let (Some(previous_s), Some(period_s)) = (newest_s, meta.period_s) else {
        return Ok(());
    };
    let gap_s = time_s - previous_s;
    if gap_s == 0.0 || gap_s >= period_s * (1.0 - PERIOD_TOLERANCE) {
        return Ok(());
    }
    Err(DataError::CommitTooSoon {
        topic: meta.name.clone(),
        publisher: meta.publisher.clone(),
        time_s,
        previous_s,
        gap_s,
        period_s,
    })
}

fn downcast<T: TopicValue>(topic: &dyn ErasedTopic) -> Option<&Topic<T>> {
    let topic: &dyn Any = topic;
    topic.downcast_ref()
}

fn downcast_mut<T: TopicValue>(topic: &mut dyn ErasedTopic) -> Option<&mut Topic<T>> {
    let topic: &mut dyn Any = topic;
    topic.downcast_mut()
}

impl DataManager {
    fn typed<T: TopicValue>(&self, slot: usize) -> Result<(&TopicMeta, &Topic<T>), DataError> {
        self.slots
            .get(slot)
            .and_then(|s| Some((&s.meta, downcast::<T>(&*s.topic)?)))
            .ok_or(DataError::ForeignHandle {
                type_name: type_name::<T>(),
                slot,
            })
    }

    fn typed_mut<T: TopicValue>(
        &mut self,
        slot: usize,
    ) -> Result<(&TopicMeta, &mut Topic<T>), DataError> {
        self.slots
            .get_mut(slot)
            .and_then(|s| Some((&s.meta, downcast_mut::<T>(&mut *s.topic)?)))
            .ok_or(DataError::ForeignHandle {
                type_name: type_name::<T>(),
                slot,
            })
    }

    fn reader_name(&self, reader: usize) -> String {
        self.readers.get(reader).cloned().unwrap_or_default()
    }

    /// Publishes `value` as the topic's new iterate at `time_s` (s); returns its version.
    pub fn publish<T: TopicValue>(
        &mut self,
        handle: Publisher<T>,
        time_s: f64,
        value: T,
    ) -> Result<u64, DataError> {
        let (meta, topic) = self.typed_mut::<T>(handle.slot)?;
        check_publication(meta, topic.state.newest().map(|s| s.time_s), time_s)?;
        Ok(topic.state.set_head(time_s, value))
    }

    /// Publishes a new iterate at `time_s` (s) by updating the head in place (created with
    /// `T::default()` the first time), so a region refills its buffers without allocating;
    /// returns its version.
    pub fn publish_with<T: TopicValue + Default>(
        &mut self,
        handle: Publisher<T>,
        time_s: f64,
        update: impl FnOnce(&mut T),
    ) -> Result<u64, DataError> {
        let (meta, topic) = self.typed_mut::<T>(handle.slot)?;
        check_publication(meta, topic.state.newest().map(|s| s.time_s), time_s)?;
        Ok(topic.state.update_head(time_s, update))
    }

    /// Commits the topic's pending iterate into its history; false if nothing was pending.
    pub fn mark_converged<T: TopicValue>(
        &mut self,
        handle: Publisher<T>,
    ) -> Result<bool, DataError> {
        let (meta, topic) = self.typed_mut::<T>(handle.slot)?;
        let Some(time_s) = ErasedTopic::pending_time(topic) else {
            return Ok(false);
        };
        check_commit(meta, topic.newest_time(), time_s)?;
        Ok(topic.commit_head())
    }

    /// Commits every pending iterate stamped at or before `up_to_s` (s), all or none; returns
    /// how many topics were committed. Iterates stamped later stay pending.
    pub fn commit(&mut self, up_to_s: f64) -> Result<usize, DataError> {
        if !up_to_s.is_finite() {
            return Err(DataError::NonFiniteCommitTime { time_s: up_to_s });
        }
        let due = |topic: &dyn ErasedTopic| topic.pending_time().filter(|&t| t <= up_to_s);
        for slot in &self.slots {
            if let Some(time_s) = due(&*slot.topic) {
                check_commit(&slot.meta, slot.topic.newest_time(), time_s)?;
            }
        }
        let mut committed = 0;
        for slot in &mut self.slots {
            if due(&*slot.topic).is_some() && slot.topic.commit_head() {
                committed += 1;
            }
        }
        Ok(committed)
    }

    /// The topic's latest publication (iterate or converged), or an error naming the topic and
    /// reader if nothing was published yet.
    pub fn read<T: TopicValue>(&self, handle: Subscriber<T>) -> Result<Stamped<'_, T>, DataError> {
        let (meta, topic) = self.typed::<T>(handle.slot)?;
        match &topic.state.head {
            Some(head) => Ok(head.sample.stamped(head.converged)),
            None => Err(DataError::NotYetPublished {
                topic: meta.name.clone(),
                reader: self.reader_name(handle.reader),
            }),
        }
    }

    /// The topic's newest converged value.
    pub fn read_converged<T: TopicValue>(
        &self,
        handle: Subscriber<T>,
    ) -> Result<Stamped<'_, T>, DataError> {
        let (meta, topic) = self.typed::<T>(handle.slot)?;
        match topic.state.newest() {
            Some(sample) => Ok(sample.stamped(true)),
            None => Err(DataError::NothingConverged {
                topic: meta.name.clone(),
                reader: self.reader_name(handle.reader),
            }),
        }
    }

    /// The converged value at `time_s` (s) into `out`: linear between the bracketing values of
    /// an interpolated topic, the earlier one of a held topic, the newest beyond it. Iterates are
    /// not seen. Errors name topic and reader when `time_s` is older than the history kept.
    pub fn read_at<T: TopicValue>(
        &self,
        handle: Subscriber<T>,
        time_s: f64,
        out: &mut T,
    ) -> Result<Bracket, DataError> {
        let (meta, topic) = self.typed::<T>(handle.slot)?;
        let topic_name = || meta.name.clone();
        let reader = || self.reader_name(handle.reader);
        if !time_s.is_finite() {
            return Err(DataError::NonFiniteTime {
                topic: topic_name(),
                region: reader(),
                time_s,
            });
        }
        topic.sample_at(time_s, out).map_err(|miss| match miss {
            Miss::Empty => DataError::NothingConverged {
                topic: topic_name(),
                reader: reader(),
            },
            Miss::TooOld { oldest_s } => DataError::ReadBeforeHistory {
                topic: topic_name(),
                reader: reader(),
                time_s,
                oldest_s,
            },
            Miss::Shape(shape) => DataError::ShapeChanged {
                topic: topic_name(),
                reader: reader(),
                time_s,
                earlier: shape.earlier,
                later: shape.later,
            },
        })
    }

    /// The converged values kept for the topic, oldest first.
    pub fn history<T: TopicValue>(
        &self,
        handle: Subscriber<T>,
    ) -> Result<impl Iterator<Item = Stamped<'_, T>>, DataError> {
        let (_, topic) = self.typed::<T>(handle.slot)?;
        let state = &topic.state;
        Ok((0..state.history.len()).map(move |rank| state.at(rank).stamped(true)))
    }

    /// Version of the topic's latest publication (0 before the first one).
    pub fn version<T: TopicValue>(&self, handle: Subscriber<T>) -> u64 {
        self.typed::<T>(handle.slot)
            .map_or(0, |(_, topic)| topic.state.version())
    }

    /// Names of all topics, in declaration order.
    pub fn topic_names(&self) -> impl Iterator<Item = &str> {
        self.slots.iter().map(|s| s.meta.name.as_str())
    }

    /// Every topic as assembled, in declaration order.
    pub fn topics(&self) -> impl Iterator<Item = TopicInfo<'_>> {
        self.slots.iter().map(|s| TopicInfo {
            name: &s.meta.name,
            publisher: &s.meta.publisher,
            type_name: s.meta.type_name,
            period_s: s.meta.period_s,
            interpolation: s.meta.interpolation,
            history_depth: s.meta.history_depth,
        })
    }

    /// A copy of the whole exchange state: heads, rings, versions.
    pub fn checkpoint(&self) -> DataCheckpoint {
        let topics = self.slots.iter().map(|s| TopicCheckpoint {
            name: s.meta.name.clone(),
            type_name: s.meta.type_name.to_owned(),
            state: CheckpointState::Typed(s.topic.snapshot()),
        });
        DataCheckpoint {
            topics: topics.collect(),
        }
    }

    /// Overwrites `into` with the exchange state, reusing its buffers when it was taken from
    /// the same topic table.
    pub fn checkpoint_into(&self, into: &mut DataCheckpoint) {
        if !self.same_table(into) {
            *into = self.checkpoint();
            return;
        }
        for (slot, entry) in self.slots.iter().zip(&mut into.topics) {
            let reused = match &mut entry.state {
                CheckpointState::Typed(state) => slot.topic.snapshot_into(&mut **state),
                CheckpointState::Serialized(_) => false,
            };
            if !reused {
                entry.state = CheckpointState::Typed(slot.topic.snapshot());
            }
        }
    }

    fn same_table(&self, checkpoint: &DataCheckpoint) -> bool {
        self.slots.len() == checkpoint.topics.len()
            && self
                .slots
                .iter()
                .zip(&checkpoint.topics)
                .all(|(slot, entry)| slot.meta.name == entry.name)
    }

    /// Returns the manager to the state `checkpoint` was taken in, bit for bit, or changes
    /// nothing and names the topic that does not fit.
    pub fn restore(&mut self, checkpoint: &DataCheckpoint) -> Result<(), DataError> {
        if !self.same_table(checkpoint) {
            return Err(DataError::CheckpointTopics {
                expected: self.topic_names().collect::<Vec<_>>().join(", "),
                found: checkpoint.topic_names().collect::<Vec<_>>().join(", "),
            });
        }
        let parsed = self.parse_serialized(checkpoint)?;
        let state_of = |index: usize| -> Option<&dyn ErasedState> {
            match &checkpoint.topics[index].state {
                CheckpointState::Typed(state) => Some(&**state),
                CheckpointState::Serialized(_) => parsed.get(index)?.as_deref(),
            }
        };
        for (index, slot) in self.slots.iter().enumerate() {
            let checked = match state_of(index) {
                Some(state) => slot.topic.check_state(state),
                None => Err("its state is missing".to_owned()),
            };
            checked.map_err(|reason| DataError::CheckpointState {
                topic: slot.meta.name.clone(),
                reason,
            })?;
        }
        for (index, slot) in self.slots.iter_mut().enumerate() {
            if let Some(state) = state_of(index) {
                slot.topic.restore(state);
            }
        }
        Ok(())
    }

    /// Typed states for the serialized topics of a checkpoint read from a file (no allocation
    /// when every state is already typed).
    fn parse_serialized(
        &self,
        checkpoint: &DataCheckpoint,
    ) -> Result<Vec<Option<Box<dyn ErasedState>>>, DataError> {
        let any_serialized = checkpoint
            .topics
            .iter()
            .any(|t| matches!(t.state, CheckpointState::Serialized(_)));
        if !any_serialized {
            return Ok(Vec::new());
        }
        let parse = |(slot, entry): (&Slot, &TopicCheckpoint)| match &entry.state {
            CheckpointState::Typed(_) => Ok(None),
            CheckpointState::Serialized(value) => {
                slot.topic.parse_state(value).map(Some).map_err(|reason| {
                    DataError::CheckpointState {
                        topic: slot.meta.name.clone(),
                        reason,
                    }
                })
            }
        };
        self.slots
            .iter()
            .zip(&checkpoint.topics)
            .map(parse)
            .collect()
    }
}

// ---------------------------------------------------------------------------------------------
// Checkpoints
// ---------------------------------------------------------------------------------------------

enum CheckpointState {
    /// Taken from a manager: the typed state, restored by copying.
    Typed(Box<dyn ErasedState>),
    /// Read from a file: parsed into the topic's type on restore.
    Serialized(Value),
}

impl Clone for CheckpointState {
    fn clone(&self) -> Self {
        match self {
            Self::Typed(state) => Self::Typed(state.clone_state()),
            Self::Serialized(value) => Self::Serialized(value.clone()),
        }
    }
}

#[derive(Clone)]
struct TopicCheckpoint {
    name: String,
    type_name: String,
    state: CheckpointState,
}

/// The whole exchange state of a [`DataManager`] (heads, rings, versions), plain data: Clone,
/// and serde-serializable for restart files (bit-exact floats, see the module docs).
#[derive(Clone)]
pub struct DataCheckpoint {
    topics: Vec<TopicCheckpoint>,
}

impl DataCheckpoint {
    /// Names of the topics held, in the order of the manager's table.
    pub fn topic_names(&self) -> impl Iterator<Item = &str> {
        self.topics.iter().map(|t| t.name.as_str())
    }
}

impl fmt::Debug for DataCheckpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let topics = self.topics.iter().map(|t| (&t.name, &t.type_name));
        f.debug_struct("DataCheckpoint")
            .field("topics", &topics.collect::<Vec<_>>())
            .finish()
    }
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CheckpointFile {
    format: u32,
    topics: Vec<TopicFile>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct TopicFile {
    name: String,
    /// Rust type name, for the reader's information only (not stable across compilers).
    type_name: String,
    state: Value,
}

impl TopicCheckpoint {
    fn to_file(&self) -> Result<TopicFile, String> {
        let mut state = match &self.state {
            CheckpointState::Typed(state) => state
                .to_value()
                .map_err(|e| format!("topic `{}`: {e}", self.name))?,
            CheckpointState::Serialized(value) => value.clone(),
        };
        encode_floats(&mut state);
        Ok(TopicFile {
            name: self.name.clone(),
            type_name: self.type_name.clone(),
            state,
        })
    }

    fn from_file(mut file: TopicFile) -> Result<Self, String> {
        decode_floats(&mut file.state).map_err(|e| format!("topic `{}`: {e}", file.name))?;
        Ok(Self {
            name: file.name,
            type_name: file.type_name,
            state: CheckpointState::Serialized(file.state),
        })
    }
}

impl Serialize for DataCheckpoint {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let topics = self
            .topics
            .iter()
            .map(TopicCheckpoint::to_file)
            .collect::<Result<Vec<_>, _>>()
            .map_err(S::Error::custom)?;
        CheckpointFile {
            format: CHECKPOINT_FORMAT,
            topics,
        }
        .serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for DataCheckpoint {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let file = CheckpointFile::deserialize(deserializer)?;
        if file.format != CHECKPOINT_FORMAT {
            return Err(D::Error::custom(format!(
                "data checkpoint format {} is not the supported format {CHECKPOINT_FORMAT}",
                file.format
            )));
        }
        let topics = file
            .topics
            .into_iter()
            .map(TopicCheckpoint::from_file)
            .collect::<Result<Vec<_>, _>>()
            .map_err(D::Error::custom)?;
        Ok(Self { topics })
    }
}

/// Rewrites every float as `{"$f64": "<shortest round-trip decimal>"}` (Rust's `{:?}` of `f64`
/// round-trips exactly through `str::parse`), so no JSON parser's float rounding touches it.
fn encode_floats(value: &mut Value) {
    match value {
        Value::Number(number) if number.is_f64() => {
            if let Some(x) = number.as_f64() {
                let mut tagged = serde_json::Map::new();
                tagged.insert(FLOAT_TAG.to_owned(), Value::String(format!("{x:?}")));
                *value = Value::Object(tagged);
            }
        }
        Value::Array(items) => items.iter_mut().for_each(encode_floats),
        Value::Object(fields) => fields.values_mut().for_each(encode_floats),
        _ => {}
    }
}

/// Inverse of [`encode_floats`].
fn decode_floats(value: &mut Value) -> Result<(), String> {
    match value {
        Value::Object(fields) if fields.len() == 1 && fields.contains_key(FLOAT_TAG) => {
            let text = fields.get(FLOAT_TAG).and_then(Value::as_str).unwrap_or("");
            let number = text
                .parse::<f64>()
                .ok()
                .and_then(Number::from_f64)
                .ok_or_else(|| format!("`{text}` is not a finite float"))?;
            *value = Value::Number(number);
            Ok(())
        }
        Value::Array(items) => items.iter_mut().try_for_each(decode_floats),
        Value::Object(fields) => fields.values_mut().try_for_each(decode_floats),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subscriber_reads_what_publisher_wrote_with_stamps() {
        let mut builder = DataManagerBuilder::new();
        let root_motion = builder
            .publish::<[f64; 2]>("main-body", "root-motion")
            .unwrap();
        let reader = builder
            .subscribe::<[f64; 2]>("left-surface", "root-motion")
            .unwrap();
        let mut data = builder.build().unwrap();
        assert!(matches!(
            data.read(reader),
            Err(DataError::NotYetPublished { .. })
        ));
        data.publish(root_motion, 0.001, [1.0, 2.0]).unwrap();
        data.publish(root_motion, 0.002, [3.0, 4.0]).unwrap();
        let read = data.read(reader).unwrap();
        assert_eq!(*read.value, [3.0, 4.0]);
        assert_eq!(read.time_s, 0.002);
        assert_eq!(read.version, 2);
        assert!(!read.converged);
    }

    #[test]
    fn publish_with_updates_in_place() {
        let mut builder = DataManagerBuilder::new();
        let loads = builder
            .publish::<Vec<f64>>("propulsion", "engine-loads")
            .unwrap();
        let reader = builder
            .subscribe::<Vec<f64>>("main-body", "engine-loads")
            .unwrap();
        let mut data = builder.build().unwrap();
        data.publish_with(loads, 0.0, |v| v.resize(3, 1.0)).unwrap();
        let first_ptr = data.read(reader).unwrap().value.as_ptr();
        data.publish_with(loads, 0.1, |v| v.iter_mut().for_each(|x| *x = 2.0))
            .unwrap();
        let read = data.read(reader).unwrap();
        assert_eq!(read.value, &vec![2.0; 3]);
        assert_eq!(read.value.as_ptr(), first_ptr, "buffer was reallocated");
    }

    #[test]
    fn ring_reuses_value_buffers_once_it_has_filled() {
        let mut builder = DataManagerBuilder::new();
        let publisher = builder
            .publish_interpolated::<Vec<f64>>("main-body", "oml", 0.01)
            .unwrap();
        builder.subscribe::<Vec<f64>>("surface", "oml").unwrap();
        let mut data = builder.build().unwrap();
        let buffers = |data: &DataManager| {
            let topic = downcast::<Vec<f64>>(&*data.slots[0].topic).unwrap();
            let mut ptrs: Vec<_> = topic
                .state
                .history
                .iter()
                .map(|s| s.value.as_ptr())
                .collect();
            ptrs.sort();
            ptrs
        };
        let step = |data: &mut DataManager, k: u32| {
            let t = f64::from(k) * 0.01;
            data.publish_with(publisher, t, |v| {
                v.clear();
                v.extend([t; 64]);
            })
            .unwrap();
            data.commit(t).unwrap();
        };
        (0..2).for_each(|k| step(&mut data, k));
        let filled = buffers(&data);
        assert_eq!(filled.len(), MIN_HISTORY_SAMPLES);
        (2..9).for_each(|k| step(&mut data, k));
        assert_eq!(buffers(&data), filled, "a ring slot was reallocated");
    }

    #[test]
    fn assembly_rejects_orphan_subscription() {
        let mut builder = DataManagerBuilder::new();
        builder
            .publish::<f64>("main-body", "flight-condition")
            .unwrap();
        builder.subscribe::<f64>("propulsion", "body-oml").unwrap();
        let err = builder.build().err().unwrap();
        let message = err.to_string();
        assert!(message.contains("body-oml") && message.contains("propulsion"));
        assert!(message.contains("flight-condition"));
    }

    #[test]
    fn assembly_rejects_second_publisher_and_type_mismatch() {
        let mut builder = DataManagerBuilder::new();
        builder.publish::<f64>("a", "t").unwrap();
        assert!(matches!(
            builder.publish::<f64>("b", "t"),
            Err(DataError::DuplicatePublisher { .. })
        ));
        assert!(matches!(
            builder.subscribe::<u32>("c", "t"),
            Err(DataError::TypeMismatch { .. })
        ));
    }

    #[test]
    fn serialized_floats_round_trip_bit_exactly_through_json_text() {
        let awkward = [
            0.1 + 0.2,
            1.0 / 3.0,
            -0.0,
            1e-300,
            5e-324,
            f64::MAX,
            2.0_f64.sqrt(),
        ];
        let mut value = serde_json::to_value(awkward).unwrap();
        encode_floats(&mut value);
        let text = serde_json::to_string(&value).unwrap();
        let mut back: Value = serde_json::from_str(&text).unwrap();
        decode_floats(&mut back).unwrap();
        let back: Vec<f64> = serde_json::from_value(back).unwrap();
        let bits = |xs: &[f64]| xs.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&awkward));
    }
}
