//! Assembling the store: regions declare what they publish and subscribe to, with periods and
//! history; the builder checks them against each other and sizes each topic's ring.

use super::*;

/// Builds the type-erased store of one topic with a ring of the given depth.
pub(super) type MakeTopic = fn(usize) -> Box<dyn ErasedTopic>;

pub(super) struct PublisherDeclaration {
    pub(super) region: String,
    pub(super) period_s: Option<f64>,
    pub(super) interpolation: Interpolation,
    pub(super) make: MakeTopic,
}

pub(super) struct SubscriberDeclaration {
    pub(super) region: String,
    pub(super) spec: Option<SubscriptionSpec>,
}

pub(super) struct TopicDeclaration {
    pub(super) name: String,
    pub(super) type_id: TypeId,
    pub(super) type_name: &'static str,
    pub(super) declared_by: String,
    pub(super) publisher: Option<PublisherDeclaration>,
    pub(super) subscribers: Vec<SubscriberDeclaration>,
}

/// Collects the topic declarations of every region before the run starts.
#[derive(Default)]
pub struct DataManagerBuilder {
    pub(super) topics: Vec<TopicDeclaration>,
    pub(super) readers: Vec<String>,
}

impl DataManagerBuilder {
    pub fn new() -> Self {
        Self::default()
    }

    pub(super) fn declare<T: Any>(
        &mut self,
        region: &str,
        topic: &str,
    ) -> Result<usize, DataError> {
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

    pub(super) fn declare_publisher<T: TopicValue>(
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

    /// Declares that `region` commits `topic` at most every `period_s` seconds; reads between
    /// values interpolate linearly and reads past the newest extrapolate from the two newest
    /// ([`Interpolation::Predicted`]).
    pub fn publish_predicted<T: TopicValue + Interpolate>(
        &mut self,
        region: &str,
        topic: &str,
        period_s: f64,
    ) -> Result<Publisher<T>, DataError> {
        let make = predicted_topic::<T>;
        self.declare_publisher(
            region,
            topic,
            Some(period_s),
            Interpolation::Predicted,
            make,
        )
    }

    pub(super) fn declare_subscriber<T: TopicValue>(
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

    pub(super) fn check_every_topic_published(&self) -> Result<(), DataError> {
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
    pub(super) fn subscriber_names(&self) -> String {
        let names: Vec<&str> = self.subscribers.iter().map(|s| s.region.as_str()).collect();
        names.join(", ")
    }

    pub(super) fn into_slot(self) -> Result<Slot, DataError> {
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
    pub(super) fn depth_for(
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
pub(super) fn samples_needed(history_s: f64, reader_period_s: f64, publisher_period_s: f64) -> f64 {
    ((history_s + reader_period_s) / publisher_period_s - 1e-9).ceil() + 2.0
}

/// A period (s) must be finite and > 0.
pub(super) fn check_period(
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
pub(super) fn check_history(topic: &str, region: &str, value: f64) -> Result<(), DataError> {
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

pub(super) fn hold_topic<T: TopicValue>(depth: usize) -> Box<dyn ErasedTopic> {
    Box::new(Topic::<T>::new(depth, clone_into::<T>, None))
}

pub(super) fn linear_topic<T: TopicValue + Interpolate>(depth: usize) -> Box<dyn ErasedTopic> {
    Box::new(Topic::<T>::new(depth, T::copy_into, Some(T::lerp_into)))
}

pub(super) fn predicted_topic<T: TopicValue + Interpolate>(depth: usize) -> Box<dyn ErasedTopic> {
    let mut topic = Topic::<T>::new(depth, T::copy_into, Some(T::lerp_into));
    topic.extrapolate = Some(T::extrapolate_into);
    Box::new(topic)
}

pub(super) fn clone_into<T: Clone>(value: &T, out: &mut T) {
    out.clone_from(value);
}
