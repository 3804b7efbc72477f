//! The data manager: typed handles to publish, read, commit and roll back, checked against each
//! topic's declaration.

use super::*;

pub(super) struct TopicMeta {
    pub(super) name: String,
    pub(super) publisher: String,
    pub(super) type_name: &'static str,
    pub(super) period_s: Option<f64>,
    pub(super) interpolation: Interpolation,
    pub(super) history_depth: usize,
}

pub(super) struct Slot {
    pub(super) meta: TopicMeta,
    pub(super) topic: Box<dyn ErasedTopic>,
}

/// The central store: per topic the latest publication (iterate or converged) and a ring of
/// converged stamped values.
pub struct DataManager {
    pub(super) slots: Vec<Slot>,
    pub(super) readers: Vec<String>,
}

impl fmt::Debug for DataManager {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.topics()).finish()
    }
}

/// A publication at `time_s` must be finite and not older than the newest converged value.
pub(super) fn check_publication(
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
pub(super) fn check_commit(
    meta: &TopicMeta,
    newest_s: Option<f64>,
    time_s: f64,
) -> Result<(), DataError> {
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

pub(super) fn downcast<T: TopicValue>(topic: &dyn ErasedTopic) -> Option<&Topic<T>> {
    let topic: &dyn Any = topic;
    topic.downcast_ref()
}

pub(super) fn downcast_mut<T: TopicValue>(topic: &mut dyn ErasedTopic) -> Option<&mut Topic<T>> {
    let topic: &mut dyn Any = topic;
    topic.downcast_mut()
}

impl DataManager {
    pub(super) fn typed<T: TopicValue>(
        &self,
        slot: usize,
    ) -> Result<(&TopicMeta, &Topic<T>), DataError> {
        self.slots
            .get(slot)
            .and_then(|s| Some((&s.meta, downcast::<T>(&*s.topic)?)))
            .ok_or(DataError::ForeignHandle {
                type_name: type_name::<T>(),
                slot,
            })
    }

    pub(super) fn typed_mut<T: TopicValue>(
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

    pub(super) fn reader_name(&self, reader: usize) -> String {
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

    pub(super) fn same_table(&self, checkpoint: &DataCheckpoint) -> bool {
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
    pub(super) fn parse_serialized(
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
