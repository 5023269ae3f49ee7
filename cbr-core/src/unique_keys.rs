//! Maps read from a file with every key once. A map that serde reads keeps the last of
//! two equal keys silently; a config, an operator file or a case file that writes a key
//! twice has said two things, and the reader should be told which key, not guess which
//! one counted. These readers (for `#[serde(deserialize_with = ...)]`) refuse the second,
//! naming it; the file format's own error gives its place (RON: line:column).
//!
//! ```
//! use serde::Deserialize;
//! use std::collections::BTreeMap;
//!
//! #[derive(Debug, Deserialize)]
//! struct Suite {
//!     #[serde(deserialize_with = "cbr_core::unique_keys::each_once")]
//!     readings: BTreeMap<String, String>,
//! }
//!
//! let twice = serde_json::from_str::<Suite>(r#"{"readings": {"a": "x", "a": "y"}}"#);
//! assert!(twice.unwrap_err().to_string().starts_with("`a` is given twice; give each key once"));
//! ```

use serde::de::{Deserialize, Deserializer, MapAccess, Visitor};
use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;

/// Reads a map, refusing a key given twice with the message `twice(key)`.
pub fn map_with_unique_keys<'de, D, K, V>(
    d: D,
    twice: fn(&K) -> String,
) -> Result<BTreeMap<K, V>, D::Error>
where
    D: Deserializer<'de>,
    K: Deserialize<'de> + Ord,
    V: Deserialize<'de>,
{
    d.deserialize_map(UniqueKeys {
        twice,
        entries: PhantomData,
    })
}

/// Reads a map whose keys are each given once: ``"`KEY` is given twice; give each key
/// once"`` otherwise.
pub fn each_once<'de, D, K, V>(d: D) -> Result<BTreeMap<K, V>, D::Error>
where
    D: Deserializer<'de>,
    K: Deserialize<'de> + Ord + fmt::Display,
    V: Deserialize<'de>,
{
    map_with_unique_keys(d, |key| {
        format!("`{key}` is given twice; give each key once")
    })
}

/// Reads a context as a file writes it, variables to values, each variable once:
/// ``"context variable `VARIABLE` is given twice; give each variable once"`` otherwise.
pub fn each_variable_once<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<BTreeMap<String, String>, D::Error> {
    map_with_unique_keys(d, |variable| {
        format!("context variable `{variable}` is given twice; give each variable once")
    })
}

/// Reads a list of contexts ([`each_variable_once`] for each).
pub fn each_variable_once_in_each<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Vec<BTreeMap<String, String>>, D::Error> {
    /// One context of the list, read by [`each_variable_once`].
    struct Once(BTreeMap<String, String>);
    impl<'de> Deserialize<'de> for Once {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            each_variable_once(d).map(Once)
        }
    }
    let contexts = Vec::<Once>::deserialize(d)?;
    Ok(contexts.into_iter().map(|Once(context)| context).collect())
}

/// The visitor of [`map_with_unique_keys`].
struct UniqueKeys<K, V> {
    twice: fn(&K) -> String,
    entries: PhantomData<fn() -> (K, V)>,
}

impl<'de, K, V> Visitor<'de> for UniqueKeys<K, V>
where
    K: Deserialize<'de> + Ord,
    V: Deserialize<'de>,
{
    type Value = BTreeMap<K, V>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a map, each key once")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut read = BTreeMap::new();
        while let Some(key) = map.next_key::<K>()? {
            if read.contains_key(&key) {
                return Err(serde::de::Error::custom((self.twice)(&key)));
            }
            let value = map.next_value::<V>()?;
            read.insert(key, value);
        }
        Ok(read)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Deserialize, PartialEq)]
    struct Spec {
        #[serde(deserialize_with = "each_variable_once")]
        when: BTreeMap<String, String>,
        #[serde(default, deserialize_with = "each_variable_once_in_each")]
        cycle: Vec<BTreeMap<String, String>>,
    }

    #[test]
    fn a_key_given_twice_is_refused_by_name_and_distinct_keys_read() {
        let good: Spec = serde_json::from_str(
            r#"{"when": {"cargo": "x", "shift": "y"}, "cycle": [{}, {"cargo": "x"}]}"#,
        )
        .unwrap();
        assert_eq!(good.when.len(), 2);
        assert_eq!(good.cycle.len(), 2);
        let err = serde_json::from_str::<Spec>(r#"{"when": {"cargo": "x", "cargo": "y"}}"#)
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("context variable `cargo` is given twice; give each variable once"),
            "{err}"
        );
        let err = serde_json::from_str::<Spec>(
            r#"{"when": {}, "cycle": [{"a": "1"}, {"b": "1", "b": "2"}]}"#,
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.starts_with("context variable `b` is given twice"),
            "{err}"
        );
    }
}
