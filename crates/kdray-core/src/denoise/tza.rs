//! Reading a Tensor Archive (TZA), the file format of Open Image Denoise's
//! trained weights: a header (magic `0x41D7`, version 2.x, the table's
//! offset), the tensors' data, then a table naming each tensor with its
//! dimensions, layout (`x` or `oihw`), data type and data offset. All
//! integers little-endian. OIDN writes f32 (`f`); f16 (`h`) is read too.
//!
//! Every read is bounds-checked: a truncated or corrupt archive is an
//! error naming what was wrong, never a panic.

/// One tensor of an archive, its values widened to f32.
#[derive(Clone, Debug, PartialEq)]
pub struct TzaTensor {
    pub name: String,
    pub dims: Vec<usize>,
    /// `x` (a vector) or `oihw` (output, input, height, width).
    pub layout: String,
    pub values: Vec<f32>,
}

const MAGIC: u16 = 0x41D7;

/// A cursor over the archive's bytes whose reads fail past the end.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&end| end <= self.bytes.len())
            .ok_or_else(|| format!("truncated: {what} runs past the end at byte {}", self.at))?;
        let slice = &self.bytes[self.at..end];
        self.at = end;
        Ok(slice)
    }

    fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.take(1, what)?[0])
    }

    fn u16(&mut self, what: &str) -> Result<u16, String> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self, what: &str) -> Result<u64, String> {
        let b = self.take(8, what)?;
        Ok(u64::from_le_bytes(std::array::from_fn(|i| b[i])))
    }
}

/// The value of an IEEE 754 half-precision number.
fn f16_to_f32(bits: u16) -> f32 {
    let sign = if bits & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let mantissa = f32::from(bits & 0x3ff);
    match exponent {
        0 => sign * mantissa * (-24f32).exp2(),
        31 if mantissa == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        e => sign * (1.0 + mantissa / 1024.0) * ((e - 15) as f32).exp2(),
    }
}

/// Every tensor of the archive `bytes`, in table order; `Err` names the
/// first thing wrong (bad magic or version, a field or tensor past the end,
/// an unknown layout or data type, dimensions that do not fit the layout).
pub fn read_tza(bytes: &[u8]) -> Result<Vec<TzaTensor>, String> {
    let mut header = Reader { bytes, at: 0 };
    if header.u16("the magic number")? != MAGIC {
        return Err("not a tensor archive (no TZA magic number)".into());
    }
    let major = header.u8("the version")?;
    let _minor = header.u8("the version")?;
    if major != 2 {
        return Err(format!("unsupported TZA version {major} (expected 2)"));
    }
    let table = header.u64("the table offset")?;
    let table = usize::try_from(table)
        .ok()
        .filter(|&t| t <= bytes.len())
        .ok_or_else(|| format!("truncated: the tensor table's offset {table} is past the end"))?;
    let mut r = Reader { bytes, at: table };
    let count = r.u32("the tensor count")?;
    let mut tensors = Vec::new();
    for _ in 0..count {
        let name_len = usize::from(r.u16("a tensor name")?);
        let name = String::from_utf8(r.take(name_len, "a tensor name")?.to_vec())
            .map_err(|_| "a tensor name is not UTF-8".to_string())?;
        let ndims = usize::from(r.u8("a tensor's dimensions")?);
        let mut dims = Vec::with_capacity(ndims);
        for _ in 0..ndims {
            dims.push(r.u32("a tensor's dimensions")? as usize);
        }
        let layout = String::from_utf8_lossy(r.take(ndims, "a tensor's layout")?).into_owned();
        if layout != "x" && layout != "oihw" {
            return Err(format!(
                "tensor {name}: unknown layout {layout:?} (expected x or oihw)"
            ));
        }
        let dtype = r.u8("a tensor's data type")?;
        let offset = r.u64("a tensor's data offset")?;
        let count = dims
            .iter()
            .try_fold(1usize, |n, &d| n.checked_mul(d))
            .ok_or_else(|| format!("tensor {name}: dimensions {dims:?} overflow"))?;
        let width = match dtype {
            b'f' => 4,
            b'h' => 2,
            other => {
                return Err(format!(
                    "tensor {name}: unsupported data type {:?} (expected f or h)",
                    other as char
                ))
            }
        };
        let mut data = Reader {
            bytes,
            at: usize::try_from(offset).unwrap_or(usize::MAX),
        };
        let raw = count
            .checked_mul(width)
            .ok_or_else(|| format!("tensor {name}: dimensions {dims:?} overflow"))
            .and_then(|n| data.take(n, &format!("tensor {name}'s data")))?;
        let values = if width == 4 {
            raw.chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect()
        } else {
            raw.chunks_exact(2)
                .map(|b| f16_to_f32(u16::from_le_bytes([b[0], b[1]])))
                .collect()
        };
        tensors.push(TzaTensor {
            name,
            dims,
            layout,
            values,
        });
    }
    Ok(tensors)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// An archive as OIDN's training scripts write one: header, each
    /// tensor's data at a 64-byte boundary, then the table.
    pub(crate) fn write_tza(tensors: &[(&str, &[usize], &str, &[f32])]) -> Vec<u8> {
        let pad = |b: &mut Vec<u8>| b.resize(b.len().div_ceil(64) * 64, 0);
        let mut bytes = Vec::new();
        bytes.extend_from_slice(&MAGIC.to_le_bytes());
        bytes.extend_from_slice(&[2, 0]);
        bytes.extend_from_slice(&0u64.to_le_bytes());
        let mut offsets = Vec::new();
        for (_, _, _, values) in tensors {
            pad(&mut bytes);
            offsets.push(bytes.len() as u64);
            for v in *values {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        pad(&mut bytes);
        let table = bytes.len() as u64;
        bytes[4..12].copy_from_slice(&table.to_le_bytes());
        bytes.extend_from_slice(&(tensors.len() as u32).to_le_bytes());
        for ((name, dims, layout, _), offset) in tensors.iter().zip(offsets) {
            bytes.extend_from_slice(&(name.len() as u16).to_le_bytes());
            bytes.extend_from_slice(name.as_bytes());
            bytes.push(dims.len() as u8);
            for d in *dims {
                bytes.extend_from_slice(&(*d as u32).to_le_bytes());
            }
            bytes.extend_from_slice(layout.as_bytes());
            bytes.push(b'f');
            bytes.extend_from_slice(&offset.to_le_bytes());
        }
        bytes
    }

    #[test]
    fn an_archive_reads_back_its_tensors() {
        let bias = [1.5, -2.0];
        let weight: Vec<f32> = (0..2 * 3 * 3 * 3).map(|i| i as f32 * 0.25).collect();
        let bytes = write_tza(&[
            ("c.weight", &[2, 3, 3, 3], "oihw", &weight),
            ("c.bias", &[2], "x", &bias),
        ]);
        let tensors = read_tza(&bytes).unwrap();
        assert_eq!(tensors.len(), 2);
        assert_eq!(tensors[0].name, "c.weight");
        assert_eq!(tensors[0].dims, [2, 3, 3, 3]);
        assert_eq!(tensors[0].values, weight);
        assert_eq!(tensors[1].layout, "x");
        assert_eq!(tensors[1].values, bias);
    }

    /// Every truncation of a valid archive is an error, never a panic.
    #[test]
    fn every_truncation_is_an_error() {
        let bytes = write_tza(&[("b", &[3], "x", &[1.0, 2.0, 3.0])]);
        for len in 0..bytes.len() {
            assert!(read_tza(&bytes[..len]).is_err(), "{len} bytes read");
        }
    }

    #[test]
    fn bad_magic_version_layout_and_type_are_named() {
        let good = write_tza(&[("b", &[1], "x", &[1.0])]);
        let mut bad = good.clone();
        bad[0] ^= 1;
        assert!(read_tza(&bad).unwrap_err().contains("magic"));
        let mut bad = good.clone();
        bad[2] = 3;
        assert!(read_tza(&bad).unwrap_err().contains("version 3"));
        let table = u64::from_le_bytes(good[4..12].try_into().unwrap()) as usize;
        // count (4), name length (2), "b", ndims (1), dim (4): the layout.
        let layout_at = table + 4 + 2 + 1 + 1 + 4;
        let mut bad = good.clone();
        bad[layout_at] = b'q';
        assert!(read_tza(&bad).unwrap_err().contains("layout"));
        let mut bad = good;
        bad[layout_at + 1] = b'd';
        assert!(read_tza(&bad).unwrap_err().contains("data type"));
    }

    #[test]
    fn half_floats_are_widened_exactly() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(f16_to_f32(0x7c00), f32::INFINITY);
        assert!(f16_to_f32(0x7e00).is_nan());
    }
}
