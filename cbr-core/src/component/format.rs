//! The stored form of [`Values`] in RON and JSON: `Numeric(min: 0.5, step: 0.5, count:
//! 20)`, `Categorical(labels: [...], similarity: ...)` and `Custom(kind: "log-grid",
//! definition: ...)`.
//!
//! The built-in kinds keep the form they always had (case bases store their space in it).
//! Each field is checked where it is read, so a parser reports the position of the
//! offending value; unknown fields are refused. A custom kind is found by name in the
//! registry.

use super::categorical::deserialize_labels;
use super::numeric::{deserialize_count, deserialize_min, deserialize_step};
use super::registry::{self, RegistryError};
use super::{Categorical, NumericGrid, Values};
use serde::{Deserialize, Serialize};

#[derive(Serialize, Deserialize)]
#[serde(rename = "Values", deny_unknown_fields)]
pub(super) enum StoredValues {
    Numeric {
        #[serde(deserialize_with = "deserialize_min")]
        min: f64,
        #[serde(deserialize_with = "deserialize_step")]
        step: f64,
        #[serde(deserialize_with = "deserialize_count")]
        count: u16,
    },
    Categorical {
        #[serde(deserialize_with = "deserialize_labels")]
        labels: Vec<String>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        similarity: Option<Vec<Vec<f64>>>,
    },
    Custom {
        kind: String,
        definition: serde_json::Value,
    },
}

impl TryFrom<StoredValues> for Values {
    type Error = RegistryError;

    fn try_from(stored: StoredValues) -> Result<Self, Self::Error> {
        Ok(match stored {
            StoredValues::Numeric { min, step, count } => {
                Values::Numeric(NumericGrid { min, step, count })
            }
            StoredValues::Categorical { labels, similarity } => {
                Values::Categorical(Categorical { labels, similarity })
            }
            StoredValues::Custom { kind, definition } => {
                Values::Custom(registry::read(&kind, &definition)?)
            }
        })
    }
}

impl From<Values> for StoredValues {
    fn from(values: Values) -> Self {
        match values {
            Values::Numeric(NumericGrid { min, step, count }) => {
                StoredValues::Numeric { min, step, count }
            }
            Values::Categorical(Categorical { labels, similarity }) => {
                StoredValues::Categorical { labels, similarity }
            }
            Values::Custom(custom) => StoredValues::Custom {
                kind: custom.kind().to_owned(),
                definition: custom.definition().clone(),
            },
        }
    }
}
