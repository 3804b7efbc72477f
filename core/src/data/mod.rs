//! The exchange store regions talk through (the paper, §III): typed topics holding the latest
//! iterate, a ring of converged stamped values read at any time, and checkpoints of it all (one
//! file: the root holds the errors, handles, stamps and the `Interpolate` trait with its value
//! impls that every submodule shares; the store itself is in `manager`, `assembly`, `topic` and
//! `checkpoint`).
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
//! and held from the newest value beyond it (zero-order hold, no extrapolation). Topics declared
//! with [`DataManagerBuilder::publish_predicted`] interpolate linearly inside their history and
//! extrapolate beyond it from their last two converged values, `x₁ + (t − t₁)(x₁ − x₀)/(t₁ − t₀)`:
//! the predictor of explicit partitioned schemes (Farhat & Lesoinne 2000, Comput. Methods Appl.
//! Mech. Engrg. 182), by which a region evaluated once per step serves every stage of it.
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

mod assembly;
mod checkpoint;
mod manager;
mod topic;

pub use assembly::*;
pub use checkpoint::*;
pub use manager::*;
use topic::*;

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
    #[error(
        "topic `{topic}`: `{reader}` reads {expected} entries but the value read at t = {time_s} s holds {published}; its publisher and reader must agree on the length"
    )]
    LengthMismatch {
        topic: String,
        reader: String,
        time_s: f64,
        published: usize,
        expected: usize,
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
    /// [`Interpolation::Linear`] inside the history and, beyond the newest value x₁ at t₁, the
    /// linear predictor `x(t) = x₁ + (t − t₁)/(t₁ − t₀) (x₁ − x₀)` from the two newest (held with
    /// one): exact on signals linear in time at any time.
    Predicted,
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

/// Values that can be read between two converged samples by linear interpolation, and past the
/// newest by linear extrapolation.
pub trait Interpolate: Clone {
    /// `out = self + w (other − self)` with `w` ∈ [0, 1] the weight of `other`; reuses `out`.
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch>;

    /// `out = newer + w (newer − self)` with `w` ≥ 0 how far past `newer` the read lies, in
    /// units of the two values' spacing; reuses `out`.
    fn extrapolate_into(&self, newer: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch>;

    /// `out = self`, reusing the storage `out` already owns.
    fn copy_into(&self, out: &mut Self) {
        out.clone_from(self);
    }
}

/// `a + w (b − a)`.
fn lerp(a: f64, b: f64, w: f64) -> f64 {
    a + w * (b - a)
}

/// `b + (b − a) w`: the linear predictor past `b` from `a` before it.
fn extrapolate(a: f64, b: f64, w: f64) -> f64 {
    b + (b - a) * w
}

impl Interpolate for f64 {
    fn lerp_into(&self, other: &f64, w: f64, out: &mut f64) -> Result<(), ShapeMismatch> {
        *out = lerp(*self, *other, w);
        Ok(())
    }

    fn extrapolate_into(&self, newer: &f64, w: f64, out: &mut f64) -> Result<(), ShapeMismatch> {
        *out = extrapolate(*self, *newer, w);
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

    fn extrapolate_into(&self, newer: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        for ((o, a), b) in out.iter_mut().zip(self).zip(newer) {
            a.extrapolate_into(b, w, o)?;
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

    fn extrapolate_into(&self, newer: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        if self.len() != newer.len() {
            return Err(ShapeMismatch {
                earlier: (self.len(), 1),
                later: (newer.len(), 1),
            });
        }
        self.copy_into(out);
        for ((o, a), b) in out.iter_mut().zip(self).zip(newer) {
            a.extrapolate_into(b, w, o)?;
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

    fn extrapolate_into(&self, newer: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        for ((o, a), b) in out.iter_mut().zip(self.iter()).zip(newer.iter()) {
            *o = extrapolate(*a, *b, w);
        }
        Ok(())
    }
}

/// Interpolation for heap-backed nalgebra matrices: shapes must agree, `out` is reused (its
/// values are overwritten, so it is only resized when its shape differs).
macro_rules! interpolate_dynamic_matrix {
    ($matrix:ty) => {
        impl Interpolate for $matrix {
            fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
                combine_into(self, other, out, |a, b| lerp(a, b, w))
            }

            fn extrapolate_into(
                &self,
                newer: &Self,
                w: f64,
                out: &mut Self,
            ) -> Result<(), ShapeMismatch> {
                combine_into(self, newer, out, |a, b| extrapolate(a, b, w))
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

/// `out[i] = f(a[i], b[i])` for two heap-backed matrices of one shape, `out` resized only when
/// its shape differs.
fn combine_into<R: nalgebra::Dim, C: nalgebra::Dim>(
    a: &nalgebra::OMatrix<f64, R, C>,
    b: &nalgebra::OMatrix<f64, R, C>,
    out: &mut nalgebra::OMatrix<f64, R, C>,
    f: impl Fn(f64, f64) -> f64,
) -> Result<(), ShapeMismatch>
where
    nalgebra::DefaultAllocator: nalgebra::allocator::Allocator<R, C>,
{
    if a.shape() != b.shape() {
        return Err(ShapeMismatch {
            earlier: a.shape(),
            later: b.shape(),
        });
    }
    if out.shape() != a.shape() {
        *out = a.clone();
    }
    for ((o, x), y) in out.iter_mut().zip(a.iter()).zip(b.iter()) {
        *o = f(*x, *y);
    }
    Ok(())
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
/// value was copied (exact time, hold, or beyond the newest value but for a predicted topic,
/// whose weight there exceeds 1).
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
