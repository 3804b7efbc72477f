//! One topic's storage: the latest iterate, the ring of converged stamped samples, and reads at
//! any time by hold or linear interpolation.

use super::*;

/// One stamped value: simulation time (s), publication count, value.
#[derive(Debug, Serialize, Deserialize)]
pub(super) struct Sample<T> {
    pub(super) time_s: f64,
    pub(super) version: u64,
    pub(super) value: T,
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
    pub(super) fn copy_from(&mut self, source: &Self, copy: CopyFn<T>) {
        self.time_s = source.time_s;
        self.version = source.version;
        copy(&source.value, &mut self.value);
    }

    pub(super) fn stamped(&self, converged: bool) -> Stamped<'_, T> {
        Stamped {
            value: &self.value,
            time_s: self.time_s,
            version: self.version,
            converged,
        }
    }

    pub(super) fn alone(&self) -> Bracket {
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
pub(super) struct Head<T> {
    pub(super) sample: Sample<T>,
    pub(super) converged: bool,
}

/// Everything a checkpoint of one topic holds: the head and the ring of converged values,
/// `history[oldest]` the oldest, in time order from there, wrapping around.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(super) struct TopicState<T> {
    pub(super) head: Option<Head<T>>,
    pub(super) history: Vec<Sample<T>>,
    pub(super) oldest: usize,
}

pub(super) type CopyFn<T> = fn(&T, &mut T);
pub(super) type LerpFn<T> = fn(&T, &T, f64, &mut T) -> Result<(), ShapeMismatch>;

impl<T: Clone> TopicState<T> {
    pub(super) fn version(&self) -> u64 {
        self.head.as_ref().map_or(0, |h| h.sample.version)
    }

    /// The `rank`-th oldest converged value.
    pub(super) fn at(&self, rank: usize) -> &Sample<T> {
        &self.history[(self.oldest + rank) % self.history.len()]
    }

    pub(super) fn newest(&self) -> Option<&Sample<T>> {
        self.history.len().checked_sub(1).map(|last| self.at(last))
    }

    /// Number of converged values stamped at or before `time_s` (binary search on the ring).
    pub(super) fn count_at_or_before(&self, time_s: f64) -> usize {
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
    pub(super) fn set_head(&mut self, time_s: f64, value: T) -> u64 {
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
    pub(super) fn update_head(&mut self, time_s: f64, update: impl FnOnce(&mut T)) -> u64
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
    pub(super) fn copy_from(&mut self, source: &Self, copy: CopyFn<T>) {
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
    pub(super) fn check_ring(&self, depth: usize) -> Result<(), String> {
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
pub(super) enum Miss {
    Empty,
    TooOld { oldest_s: f64 },
    Shape(ShapeMismatch),
}

/// The store of one topic: its state plus how values of `T` are copied and interpolated.
pub(super) struct Topic<T> {
    pub(super) state: TopicState<T>,
    pub(super) depth: usize,
    pub(super) copy: CopyFn<T>,
    pub(super) lerp: Option<LerpFn<T>>,
    /// The predictor past the newest value (topics with [`Interpolation::Predicted`]).
    pub(super) extrapolate: Option<LerpFn<T>>,
}

impl<T: TopicValue> Topic<T> {
    pub(super) fn new(depth: usize, copy: CopyFn<T>, lerp: Option<LerpFn<T>>) -> Self {
        Self {
            state: TopicState {
                head: None,
                history: Vec::with_capacity(depth),
                oldest: 0,
            },
            depth,
            copy,
            lerp,
            extrapolate: None,
        }
    }

    /// The converged value at `time_s` into `out`: interpolated or held between the bracketing
    /// values; beyond the newest, extrapolated from the two newest for a predicted topic, else
    /// held.
    pub(super) fn sample_at(&self, time_s: f64, out: &mut T) -> Result<Bracket, Miss> {
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
        if let Some(extrapolate) = self.extrapolate
            && count == len
            && len >= 2
            && earlier.time_s != time_s
        {
            let older = state.at(len - 2);
            let w = (time_s - earlier.time_s) / (earlier.time_s - older.time_s);
            extrapolate(&older.value, &earlier.value, w, out).map_err(Miss::Shape)?;
            return Ok(Bracket {
                earlier_time_s: older.time_s,
                earlier_version: older.version,
                later_time_s: earlier.time_s,
                later_version: earlier.version,
                weight: 1.0 + w,
            });
        }
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
pub(super) trait ErasedTopic: Any + Send + Sync {
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
pub(super) trait ErasedState: Any + Send + Sync {
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
