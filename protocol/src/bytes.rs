//! `#[serde(with = "crate::bytes")]` for the byte vectors that carry bulk data (read-back
//! chunks): serialised as bytes instead of a sequence of `u8`.
//!
//! Why: heapless's own impl goes through serde's sequence path, one call per byte on
//! both ends, which was a read-back's second largest cost after COBS. In postcard, bytes
//! and a sequence of `u8` are the same wire (a varint length, then the bytes), so the
//! frames do not change; self-describing formats (JSON) still get an array of numbers
//! and are still read back from one (`visit_seq`).

use core::fmt;

use heapless::Vec;
use serde::de::{Error, SeqAccess, Visitor};
use serde::{Deserializer, Serializer};

/// Writes `v` as bytes.
pub fn serialize<S: Serializer, const N: usize>(v: &Vec<u8, N>, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_bytes(v)
}

/// Reads at most `N` bytes; more is an invalid length, as heapless's own impl says.
pub fn deserialize<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<Vec<u8, N>, D::Error> {
    d.deserialize_bytes(Bytes::<N>)
}

struct Bytes<const N: usize>;

impl<'de, const N: usize> Visitor<'de> for Bytes<N> {
    type Value = Vec<u8, N>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "at most {N} bytes")
    }

    fn visit_bytes<E: Error>(self, b: &[u8]) -> Result<Self::Value, E> {
        Vec::from_slice(b).map_err(|_| E::invalid_length(b.len(), &self))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut v = Vec::new();
        while let Some(b) = seq.next_element::<u8>()? {
            v.push(b)
                .map_err(|_| A::Error::invalid_length(N + 1, &self))?;
        }
        Ok(v)
    }
}
