//! The publish-subscribe data manager regions exchange data through (the paper, §III).
//!
//! Regions never call each other. At assembly each region declares the topics it publishes and
//! the topics it subscribes to; the builder resolves every name once into a typed handle and
//! fails if a subscribed topic has no publisher, if two regions publish the same topic, or if
//! publisher and subscriber disagree on the value type. In the time loop a handle is an index:
//! no string look-up, and after the first publication of a topic no allocation either
//! ([`DataManager::publish_with`] updates the stored value in place).

use std::any::{Any, TypeId, type_name};
use std::fmt;
use std::marker::PhantomData;

/// Why assembling or reading the data manager failed.
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
    #[error("topic `{topic}` was read by `{reader}` before anything was published to it")]
    NotYetPublished { topic: String, reader: String },
}

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

/// A value as read from the data manager: the value, the simulation time it was published at (s)
/// and a version that increases by one on every publication of the topic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stamped<'a, T> {
    pub value: &'a T,
    pub time_s: f64,
    pub version: u64,
}

struct TopicDeclaration {
    name: String,
    type_id: TypeId,
    type_name: &'static str,
    declared_by: String,
    publisher: Option<String>,
    subscribers: Vec<String>,
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

    /// Declares that `region` publishes `topic`; a topic has exactly one publisher.
    pub fn publish<T: Any + Send + Sync>(
        &mut self,
        region: &str,
        topic: &str,
    ) -> Result<Publisher<T>, DataError> {
        let slot = self.declare::<T>(region, topic)?;
        let declaration = &mut self.topics[slot];
        if let Some(first) = &declaration.publisher {
            return Err(DataError::DuplicatePublisher {
                topic: topic.to_owned(),
                first: first.clone(),
                second: region.to_owned(),
            });
        }
        declaration.publisher = Some(region.to_owned());
        Ok(Publisher {
            slot,
            _value: PhantomData,
        })
    }

    /// Declares that `region` reads `topic`; checked against the publishers in [`Self::build`].
    pub fn subscribe<T: Any + Send + Sync>(
        &mut self,
        region: &str,
        topic: &str,
    ) -> Result<Subscriber<T>, DataError> {
        let slot = self.declare::<T>(region, topic)?;
        self.topics[slot].subscribers.push(region.to_owned());
        self.readers.push(region.to_owned());
        Ok(Subscriber {
            slot,
            reader: self.readers.len() - 1,
            _value: PhantomData,
        })
    }

    /// Checks that every subscribed topic has a publisher and freezes the topic table.
    pub fn build(self) -> Result<DataManager, DataError> {
        let known = || {
            let names: Vec<&str> = self
                .topics
                .iter()
                .filter(|t| t.publisher.is_some())
                .map(|t| t.name.as_str())
                .collect();
            if names.is_empty() {
                "(none)".to_owned()
            } else {
                names.join(", ")
            }
        };
        if let Some(orphan) = self.topics.iter().find(|t| t.publisher.is_none()) {
            return Err(DataError::NoPublisher {
                topic: orphan.name.clone(),
                subscribers: orphan.subscribers.join(", "),
                known: known(),
            });
        }
        let slots = self
            .topics
            .into_iter()
            .map(|t| Slot {
                name: t.name,
                value: None,
                time_s: f64::NAN,
                version: 0,
            })
            .collect();
        Ok(DataManager {
            slots,
            readers: self.readers,
        })
    }
}

struct Slot {
    name: String,
    value: Option<Box<dyn Any + Send + Sync>>,
    time_s: f64,
    version: u64,
}

/// The central store: the latest value of every topic with its time and version stamps.
pub struct DataManager {
    slots: Vec<Slot>,
    readers: Vec<String>,
}

impl DataManager {
    /// Stores `value` as the topic's latest value at time `time_s`.
    pub fn publish<T: Any + Send + Sync>(&mut self, handle: Publisher<T>, time_s: f64, value: T) {
        let slot = &mut self.slots[handle.slot];
        match slot.value.as_mut().and_then(|v| v.downcast_mut::<T>()) {
            Some(stored) => *stored = value,
            None => slot.value = Some(Box::new(value)),
        }
        slot.time_s = time_s;
        slot.version += 1;
    }

    /// Updates the topic's value in place (created with `T::default()` the first time), so a
    /// region can refill its buffers every step without allocating.
    pub fn publish_with<T: Any + Send + Sync + Default>(
        &mut self,
        handle: Publisher<T>,
        time_s: f64,
        update: impl FnOnce(&mut T),
    ) {
        let slot = &mut self.slots[handle.slot];
        if slot.value.as_ref().is_none_or(|v| !v.is::<T>()) {
            slot.value = Some(Box::new(T::default()));
        }
        if let Some(stored) = slot.value.as_mut().and_then(|v| v.downcast_mut::<T>()) {
            update(stored);
        }
        slot.time_s = time_s;
        slot.version += 1;
    }

    /// The topic's latest value, or an error naming the topic and reader if nothing was published yet.
    pub fn read<T: Any + Send + Sync>(
        &self,
        handle: Subscriber<T>,
    ) -> Result<Stamped<'_, T>, DataError> {
        let slot = &self.slots[handle.slot];
        match slot.value.as_ref().and_then(|v| v.downcast_ref::<T>()) {
            Some(value) => Ok(Stamped {
                value,
                time_s: slot.time_s,
                version: slot.version,
            }),
            None => Err(DataError::NotYetPublished {
                topic: slot.name.clone(),
                reader: self.readers[handle.reader].clone(),
            }),
        }
    }

    /// Version of the topic's latest value (0 before the first publication).
    pub fn version<T>(&self, handle: Subscriber<T>) -> u64 {
        self.slots[handle.slot].version
    }

    /// Names of all topics, in declaration order.
    pub fn topic_names(&self) -> impl Iterator<Item = &str> {
        self.slots.iter().map(|s| s.name.as_str())
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
        data.publish(root_motion, 0.001, [1.0, 2.0]);
        data.publish(root_motion, 0.002, [3.0, 4.0]);
        let read = data.read(reader).unwrap();
        assert_eq!(*read.value, [3.0, 4.0]);
        assert_eq!(read.time_s, 0.002);
        assert_eq!(read.version, 2);
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
        data.publish_with(loads, 0.0, |v| v.resize(3, 1.0));
        let first_ptr = data.read(reader).unwrap().value.as_ptr();
        data.publish_with(loads, 0.1, |v| v.iter_mut().for_each(|x| *x = 2.0));
        let read = data.read(reader).unwrap();
        assert_eq!(read.value, &vec![2.0; 3]);
        assert_eq!(read.value.as_ptr(), first_ptr, "buffer was reallocated");
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
}
