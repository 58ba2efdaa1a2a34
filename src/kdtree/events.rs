//! Sweep events of the SAH build (Wald & Havran 2006): on each axis, where
//! an object's clipped box starts, ends, or lies flat. One event is one u64,
//! `position key (32 bits) | kind (2) | object id (30)`, so that sorting
//! events by (position, kind, id) is an integer sort and a list of them is
//! compact (8 bytes an event).

use crate::geometry::Aabb;

/// Event kinds, in the order they sort at one position.
pub const END: u64 = 0;
pub const PLANAR: u64 = 1;
pub const START: u64 = 2;

/// Object ids must fit the 30 bits an event has for them (a billion objects:
/// far beyond what a scene can hold in memory).
pub const MAX_OBJECTS: usize = 1 << 30;
const ID_MASK: u64 = (1 << 30) - 1;

/// A u32 ordered as `f32::total_cmp` orders the floats: negative floats with
/// all bits flipped, the others with the sign bit set.
pub fn key(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 1 << 31
    }
}

/// The float whose [`key`] is `k`.
pub fn value(k: u32) -> f32 {
    f32::from_bits(if k >> 31 == 1 { k & !(1 << 31) } else { !k })
}

/// An event. `-0.0` is stored as `0.0`, so that equal positions have equal
/// keys.
pub fn pack(position: f32, kind: u64, id: u32) -> u64 {
    debug_assert!((id as u64) <= ID_MASK);
    ((key(position + 0.0) as u64) << 32) | (kind << 30) | id as u64
}

pub fn position_key(event: u64) -> u32 {
    (event >> 32) as u32
}

pub fn kind(event: u64) -> u64 {
    (event >> 30) & 3
}

pub fn id(event: u64) -> u32 {
    (event & ID_MASK) as u32
}

/// Appends the events of object `id` with clipped box `b` to the three
/// axes' lists: a flat side gives one planar event, any other a start and
/// an end.
pub fn push_box(lists: &mut [Vec<u64>; 3], id: u32, b: &Aabb) {
    for_each_event(id, b, |a, event| lists[a].push(event));
}

/// Calls `f(axis, event)` for each event of object `id` with clipped box
/// `b`, as [`push_box`] files them.
pub fn for_each_event(id: u32, b: &Aabb, mut f: impl FnMut(usize, u64)) {
    for a in 0..3 {
        if b.min[a] == b.max[a] {
            f(a, pack(b.min[a], PLANAR, id));
        } else {
            f(a, pack(b.min[a], START, id));
            f(a, pack(b.max[a], END, id));
        }
    }
}

/// Merges two sorted lists into one.
pub fn merge(a: Vec<u64>, b: Vec<u64>) -> Vec<u64> {
    if b.is_empty() {
        return a;
    }
    if a.is_empty() {
        return b;
    }
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i] <= b[j] {
            out.push(a[i]);
            i += 1;
        } else {
            out.push(b[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Finite floats and the awkward ones: both zeros, subnormals,
    /// infinities and NaNs of either sign.
    fn any_float() -> impl Strategy<Value = f32> {
        prop_oneof![
            any::<f32>(),
            prop::sample::select(vec![
                0.0,
                -0.0,
                f32::MIN_POSITIVE / 2.0,
                -f32::MIN_POSITIVE / 2.0,
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::NAN,
                -f32::NAN,
                f32::MAX,
                f32::MIN,
            ]),
        ]
    }

    proptest! {
        #[test]
        fn keys_sort_like_total_cmp(mut values in prop::collection::vec(any_float(), 0..200)) {
            let mut expected = values.clone();
            expected.sort_unstable_by(f32::total_cmp);
            values.sort_unstable_by_key(|&x| key(x));
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&values), bits(&expected));
            for x in values {
                prop_assert_eq!(value(key(x)).to_bits(), x.to_bits());
            }
        }

        #[test]
        fn events_sort_by_position_then_kind_then_id(
            raw in prop::collection::vec((-1e3f32..1e3, 0u64..3, 0u32..1 << 30), 0..100)
        ) {
            let mut events: Vec<u64> = raw.iter().map(|&(p, k, id)| pack(p, k, id)).collect();
            events.sort_unstable();
            let mut expected = raw.clone();
            expected.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
            let got: Vec<_> = events.iter().map(|&e| (value(position_key(e)), kind(e), id(e))).collect();
            prop_assert_eq!(got, expected);
        }

        #[test]
        fn merge_is_a_sorted_union(mut a in prop::collection::vec(any::<u64>(), 0..50), mut b in prop::collection::vec(any::<u64>(), 0..50)) {
            a.sort_unstable();
            b.sort_unstable();
            let mut expected = [a.clone(), b.clone()].concat();
            expected.sort_unstable();
            prop_assert_eq!(merge(a, b), expected);
        }
    }

    #[test]
    fn negative_zero_is_zero() {
        assert_eq!(pack(-0.0, START, 7), pack(0.0, START, 7));
        assert!(pack(-1e-30, END, 0) < pack(0.0, END, 0));
    }
}
