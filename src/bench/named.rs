//! Serde for the library's named choices ([`crate::choice::Choice`]) in the
//! bench's JSON: a value is written as its name (`sah`, `short-stack`) and
//! read back by it, so `bench.json` spells choices as the command line does
//! and the choice types need no serde of their own.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::choice::Choice;

fn from_name<'de, T: Choice, D: Deserializer<'de>>(name: &str) -> Result<T, D::Error> {
    T::from_name(name).ok_or_else(|| {
        let valid: Vec<&str> = T::ALL.iter().map(|c| c.name()).collect();
        serde::de::Error::custom(format!(
            "unknown value \"{name}\" (valid: {})",
            valid.join(", ")
        ))
    })
}

/// `Option<T>` as an optional name.
pub mod option {
    use super::*;

    pub fn serialize<T: Choice, S: Serializer>(v: &Option<T>, s: S) -> Result<S::Ok, S::Error> {
        v.map(|c| c.name()).serialize(s)
    }

    pub fn deserialize<'de, T: Choice, D: Deserializer<'de>>(d: D) -> Result<Option<T>, D::Error> {
        match Option::<String>::deserialize(d)? {
            Some(name) => from_name::<T, D>(&name).map(Some),
            None => Ok(None),
        }
    }
}

/// `Vec<T>` as a list of names.
pub mod list {
    use super::*;

    pub fn serialize<T: Choice, S: Serializer>(v: &[T], s: S) -> Result<S::Ok, S::Error> {
        v.iter().map(|c| c.name()).collect::<Vec<_>>().serialize(s)
    }

    pub fn deserialize<'de, T: Choice, D: Deserializer<'de>>(d: D) -> Result<Vec<T>, D::Error> {
        Vec::<String>::deserialize(d)?
            .iter()
            .map(|name| from_name::<T, D>(name))
            .collect()
    }
}
