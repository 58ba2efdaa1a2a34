//! The decoder against streams meshoptimizer's own encoder wrote, with the
//! bytes its decoder gives (tests/models/optimised/meshopt_vectors.json,
//! made by meshopt_vectors.mjs there), and against damaged streams.

use super::*;

struct Vector {
    name: String,
    mode: Mode,
    filter: Filter,
    count: usize,
    stride: usize,
    encoded: Vec<u8>,
    decoded: Vec<u8>,
}

fn hex(text: &str) -> Vec<u8> {
    (0..text.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&text[i..i + 2], 16).unwrap())
        .collect()
}

fn vectors() -> Vec<Vector> {
    let text = include_str!("../../../../../tests/models/optimised/meshopt_vectors.json");
    let json: serde_json::Value = serde_json::from_str(text).unwrap();
    json.as_array()
        .unwrap()
        .iter()
        .map(|v| Vector {
            name: v["name"].as_str().unwrap().to_string(),
            mode: match v["mode"].as_str().unwrap() {
                "ATTRIBUTES" => Mode::Attributes,
                "TRIANGLES" => Mode::Triangles,
                _ => Mode::Indices,
            },
            filter: match v["filter"].as_str().unwrap() {
                "NONE" => Filter::None,
                "OCTAHEDRAL" => Filter::Octahedral,
                "QUATERNION" => Filter::Quaternion,
                _ => Filter::Exponential,
            },
            count: v["count"].as_u64().unwrap() as usize,
            stride: v["stride"].as_u64().unwrap() as usize,
            encoded: hex(v["encoded"].as_str().unwrap()),
            decoded: hex(v["decoded"].as_str().unwrap()),
        })
        .collect()
}

#[test]
fn every_mode_and_filter_decodes_as_meshoptimizer_does() {
    let all = vectors();
    assert!(all.len() >= 11);
    for v in &all {
        let out = decode(&v.encoded, v.count, v.stride, v.mode, v.filter)
            .unwrap_or_else(|e| panic!("{}: {e}", v.name));
        // The filters are specified to one unit in the last place.
        let exact = matches!(v.filter, Filter::None | Filter::Exponential);
        if exact {
            assert_eq!(out, v.decoded, "{}", v.name);
        } else {
            assert_eq!(out.len(), v.decoded.len());
            let wide = v.stride == 8;
            let values = |b: &[u8]| -> Vec<i32> {
                if wide {
                    b.chunks(2)
                        .map(|c| i32::from(i16::from_le_bytes([c[0], c[1]])))
                        .collect()
                } else {
                    b.iter().map(|&x| i32::from(x as i8)).collect()
                }
            };
            for (i, (a, b)) in values(&out).iter().zip(values(&v.decoded)).enumerate() {
                assert!((a - b).abs() <= 1, "{} value {i}: {a} vs {b}", v.name);
            }
        }
    }
}

#[test]
fn damaged_streams_are_errors_or_garbage_but_never_panics() {
    for v in vectors() {
        // Every truncation is refused: each stream needs its tail.
        for cut in [1, 2, v.encoded.len() / 2, v.encoded.len() - 1] {
            let short = &v.encoded[..v.encoded.len() - cut];
            assert!(
                decode(short, v.count, v.stride, v.mode, v.filter).is_err(),
                "{} cut by {cut}",
                v.name
            );
        }
        // Bit flips may decode to other bytes; they must not panic, and
        // what decodes has the declared size.
        for at in (0..v.encoded.len()).step_by(3) {
            for bit in [0, 3, 7] {
                let mut bad = v.encoded.clone();
                bad[at] ^= 1 << bit;
                if let Ok(out) = decode(&bad, v.count, v.stride, v.mode, v.filter) {
                    assert_eq!(out.len(), v.count * v.stride, "{}", v.name);
                }
            }
        }
    }
}

#[test]
fn counts_the_stream_cannot_hold_are_refused_before_allocating() {
    let v = &vectors()[0];
    for (mode, stride) in [
        (Mode::Attributes, 4),
        (Mode::Triangles, 4),
        (Mode::Indices, 4),
    ] {
        let err = decode(&v.encoded, 3 << 40, stride, mode, Filter::None).unwrap_err();
        assert!(err.contains("too short") || err.contains("header"), "{err}");
    }
    assert!(decode(&[0xa0; 40], usize::MAX, 4, Mode::Attributes, Filter::None).is_err());
}

#[test]
fn strides_and_filters_outside_the_extension_are_refused() {
    let stream = [0xa0; 64];
    assert!(decode(&stream, 1, 6, Mode::Attributes, Filter::None).is_err());
    assert!(decode(&stream, 1, 260, Mode::Attributes, Filter::None).is_err());
    assert!(decode(&stream, 1, 12, Mode::Attributes, Filter::Octahedral).is_err());
    assert!(decode(&stream, 1, 4, Mode::Attributes, Filter::Quaternion).is_err());
    assert!(decode(&stream, 3, 8, Mode::Triangles, Filter::None).is_err());
    assert!(decode(&stream, 3, 2, Mode::Indices, Filter::Octahedral).is_err());
    let versioned = [0xa1; 64];
    let err = decode(&versioned, 1, 4, Mode::Attributes, Filter::None).unwrap_err();
    assert!(err.contains("version 1"), "{err}");
}
