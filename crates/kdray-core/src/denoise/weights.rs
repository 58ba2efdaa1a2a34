//! A network's trained weights, read from a TZA archive and checked against
//! the U-Net of [`super::network`]: every convolution's `NAME.weight`
//! (`oihw`, O x I x 3 x 3) and `NAME.bias` (`x`, O), with the channel counts
//! the wiring gives for the archive's input channels (3, 6 or 9), and no
//! other tensor. Anything else is a one-line [`WeightsError`] naming the
//! file.

use std::fmt;
use std::path::Path;

use super::network::{conv_input_channels, CONV_LAYERS};
use super::tza::read_tza;

/// One convolution's weights: `weight[((o * in_channels + i) * 3 + ky) * 3 + kx]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvWeights {
    pub out_channels: usize,
    pub in_channels: usize,
    pub weight: Vec<f32>,
    pub bias: Vec<f32>,
}

/// The weights of the whole network, in [`CONV_LAYERS`] order.
#[derive(Clone, Debug, PartialEq)]
pub struct Weights {
    /// The channels of the network's input: 3 (colour), 6 (+ albedo) or 9
    /// (+ normal).
    pub input_channels: usize,
    pub convs: Vec<ConvWeights>,
}

/// Why a weights file cannot be used: `file: what`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WeightsError {
    pub file: String,
    pub message: String,
}

impl fmt::Display for WeightsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file, self.message)
    }
}

impl std::error::Error for WeightsError {}

impl Weights {
    /// Reads and checks a weights file.
    pub fn load(path: &Path) -> Result<Self, WeightsError> {
        let file = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| WeightsError {
            file: file.clone(),
            message: format!("cannot read the weights: {e}"),
        })?;
        Self::from_tza(&bytes, &file)
    }

    /// Checks the archive `bytes`; `file` names it in errors.
    pub fn from_tza(bytes: &[u8], file: &str) -> Result<Self, WeightsError> {
        let error = |message: String| WeightsError {
            file: file.to_string(),
            message,
        };
        let tensors = read_tza(bytes).map_err(|m| error(format!("bad weights: {m}")))?;
        for t in &tensors {
            let known = CONV_LAYERS.iter().any(|l| {
                t.name
                    .strip_prefix(l.name)
                    .is_some_and(|rest| rest == ".weight" || rest == ".bias")
            });
            if !known {
                return Err(error(format!(
                    "bad weights: unexpected tensor {} (not a layer of the U-Net)",
                    t.name
                )));
            }
        }
        let find = |name: String| {
            tensors
                .iter()
                .find(|t| t.name == name)
                .ok_or_else(|| error(format!("bad weights: no tensor {name}")))
        };
        let first = find(format!("{}.weight", CONV_LAYERS[0].name))?;
        let input_channels = match first.dims.as_slice() {
            [_, i, 3, 3] if matches!(i, 3 | 6 | 9) => *i,
            dims => {
                return Err(error(format!(
                    "bad weights: {}.weight has shape {dims:?}, expected [32, 3|6|9, 3, 3]",
                    CONV_LAYERS[0].name
                )))
            }
        };
        let in_channels = conv_input_channels(input_channels);
        let mut convs = Vec::with_capacity(CONV_LAYERS.len());
        for (layer, ic) in CONV_LAYERS.iter().zip(in_channels) {
            let oc = layer.out_channels;
            let weight = find(format!("{}.weight", layer.name))?;
            let bias = find(format!("{}.bias", layer.name))?;
            if weight.dims != [oc, ic, 3, 3] || weight.layout != "oihw" {
                return Err(error(format!(
                    "bad weights: {}.weight is {:?} {}, expected [{oc}, {ic}, 3, 3] oihw",
                    layer.name, weight.dims, weight.layout
                )));
            }
            if bias.dims != [oc] || bias.layout != "x" {
                return Err(error(format!(
                    "bad weights: {}.bias is {:?} {}, expected [{oc}] x",
                    layer.name, bias.dims, bias.layout
                )));
            }
            if let Some(bad) = weight
                .values
                .iter()
                .chain(&bias.values)
                .find(|v| !v.is_finite())
            {
                return Err(error(format!(
                    "bad weights: {} holds a non-finite value ({bad})",
                    layer.name
                )));
            }
            convs.push(ConvWeights {
                out_channels: oc,
                in_channels: ic,
                weight: weight.values.clone(),
                bias: bias.values.clone(),
            });
        }
        Ok(Weights {
            input_channels,
            convs,
        })
    }

    /// Weights of the right shapes drawn from a fixed pseudo-random
    /// sequence (for tests of the wiring and of the GPU's arithmetic),
    /// scaled so that activations stay of order one through the network.
    pub fn pseudo_random(input_channels: usize, seed: u64) -> Self {
        let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
        };
        let in_channels = conv_input_channels(input_channels);
        let convs = CONV_LAYERS
            .iter()
            .zip(in_channels)
            .map(|(layer, ic)| {
                let scale = (2.0 / (9.0 * ic as f32)).sqrt() * 1.7;
                ConvWeights {
                    out_channels: layer.out_channels,
                    in_channels: ic,
                    weight: (0..layer.out_channels * ic * 9)
                        .map(|_| next() * scale)
                        .collect(),
                    bias: (0..layer.out_channels).map(|_| next() * 0.1).collect(),
                }
            })
            .collect();
        Weights {
            input_channels,
            convs,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tza::tests::write_tza;
    use super::*;

    /// A tensor to write: name, dimensions, layout, values.
    type Entry = (String, Vec<usize>, String, Vec<f32>);
    type Edit = Box<dyn FnOnce(&mut Vec<Entry>)>;

    /// The archive of `weights`, through `edit` (which may drop or change
    /// tensors) before it is written.
    fn archive(weights: &Weights, edit: impl FnOnce(&mut Vec<Entry>)) -> Vec<u8> {
        let mut tensors = Vec::new();
        for (layer, conv) in CONV_LAYERS.iter().zip(&weights.convs) {
            tensors.push((
                format!("{}.weight", layer.name),
                vec![conv.out_channels, conv.in_channels, 3, 3],
                "oihw".to_string(),
                conv.weight.clone(),
            ));
            tensors.push((
                format!("{}.bias", layer.name),
                vec![conv.out_channels],
                "x".to_string(),
                conv.bias.clone(),
            ));
        }
        edit(&mut tensors);
        let refs: Vec<(&str, &[usize], &str, &[f32])> = tensors
            .iter()
            .map(|(n, d, l, v)| (n.as_str(), d.as_slice(), l.as_str(), v.as_slice()))
            .collect();
        write_tza(&refs)
    }

    #[test]
    fn weights_round_trip_through_an_archive() {
        for input_channels in [3, 9] {
            let weights = Weights::pseudo_random(input_channels, 7);
            let back = Weights::from_tza(&archive(&weights, |_| {}), "w.tza").unwrap();
            assert_eq!(back, weights);
        }
    }

    #[test]
    fn a_missing_reshaped_or_extra_tensor_is_one_line_naming_the_file() {
        let weights = Weights::pseudo_random(9, 1);
        let cases: Vec<(Edit, &str)> = vec![
            (
                Box::new(|t: &mut Vec<Entry>| t.retain(|x| x.0 != "dec_conv2b.bias")),
                "no tensor dec_conv2b.bias",
            ),
            (
                Box::new(|t: &mut Vec<Entry>| {
                    t[4].1 = vec![48, 16, 3, 6];
                }),
                "enc_conv2.weight is [48, 16, 3, 6]",
            ),
            (
                Box::new(|t: &mut Vec<Entry>| {
                    t.push(("extra".into(), vec![1], "x".into(), vec![0.0]))
                }),
                "unexpected tensor extra",
            ),
            (
                Box::new(|t: &mut Vec<Entry>| t[1].3[0] = f32::NAN),
                "non-finite",
            ),
        ];
        for (edit, expected) in cases {
            let error = Weights::from_tza(&archive(&weights, edit), "nets/w.tza").unwrap_err();
            let line = error.to_string();
            assert!(line.starts_with("nets/w.tza: "), "{line}");
            assert!(line.contains(expected), "{line}");
            assert!(!line.contains('\n'), "{line}");
        }
    }

    #[test]
    fn a_truncated_file_is_an_error_naming_it() {
        let bytes = archive(&Weights::pseudo_random(3, 2), |_| {});
        for len in [0, 5, 100, bytes.len() / 2, bytes.len() - 1] {
            let error = Weights::from_tza(&bytes[..len], "cut.tza").unwrap_err();
            assert!(error.to_string().starts_with("cut.tza: bad weights"));
        }
        let missing = Weights::load(Path::new("/nonexistent/w.tza")).unwrap_err();
        assert!(missing
            .to_string()
            .starts_with("/nonexistent/w.tza: cannot read"));
    }

    /// The shipped archives are OIDN's networks: the colour-only one reads
    /// 3 channels, the one with albedo and normal 9.
    #[test]
    fn the_shipped_weights_load() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/denoise");
        let hdr = Weights::load(&dir.join("rt_hdr.tza")).unwrap();
        let aux = Weights::load(&dir.join("rt_hdr_alb_nrm.tza")).unwrap();
        assert_eq!((hdr.input_channels, aux.input_channels), (3, 9));
        assert_ne!(hdr.convs[5].weight, aux.convs[5].weight);
    }
}
