//! Checkpoints of the whole store, in memory and as JSON with every float stored bit for bit.

use super::*;

pub(super) enum CheckpointState {
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
pub(super) struct TopicCheckpoint {
    pub(super) name: String,
    pub(super) type_name: String,
    pub(super) state: CheckpointState,
}

/// The whole exchange state of a [`DataManager`] (heads, rings, versions), plain data: Clone,
/// and serde-serializable for restart files (bit-exact floats, see the module docs).
#[derive(Clone)]
pub struct DataCheckpoint {
    pub(super) topics: Vec<TopicCheckpoint>,
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
pub(super) struct CheckpointFile {
    pub(super) format: u32,
    pub(super) topics: Vec<TopicFile>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TopicFile {
    pub(super) name: String,
    /// Rust type name, for the reader's information only (not stable across compilers).
    pub(super) type_name: String,
    pub(super) state: Value,
}

impl TopicCheckpoint {
    pub(super) fn to_file(&self) -> Result<TopicFile, String> {
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

    pub(super) fn from_file(mut file: TopicFile) -> Result<Self, String> {
        decode_floats(&mut file.state).map_err(|e| format!("topic `{}`: {e}", file.name))?;
        Ok(Self {
            name: file.name,
            type_name: file.type_name,
            state: CheckpointState::Serialized(file.state),
        })
    }
}

/// Two checkpoints are equal when a restart file would hold the same of them: the same topics
/// with bit-identical values (compared through their serialized form, so a checkpoint read
/// back from a file equals the one written). A checkpoint that cannot be written (non-finite
/// values) equals nothing.
impl PartialEq for DataCheckpoint {
    fn eq(&self, other: &Self) -> bool {
        match (serde_json::to_value(self), serde_json::to_value(other)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
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
pub(super) fn encode_floats(value: &mut Value) {
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
pub(super) fn decode_floats(value: &mut Value) -> Result<(), String> {
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
