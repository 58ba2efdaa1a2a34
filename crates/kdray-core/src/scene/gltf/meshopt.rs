//! The `EXT_meshopt_compression` bitstreams (the extension's Appendix A and
//! B): mode ATTRIBUTES (header 0xa0: byte-wise zigzag deltas in blocks of
//! groups of 16 elements), TRIANGLES (0xe1: edge and vertex FIFOs) and
//! INDICES (0xd1: two-baseline varint deltas), then the filters OCTAHEDRAL,
//! QUATERNION and EXPONENTIAL. Every read is checked against the stream,
//! and the smallest stream that could hold `count` elements is computed
//! before the output is allocated, so a stream claiming more elements than
//! its bytes can encode is refused without allocating (at most 64 output
//! bytes per input byte for ATTRIBUTES, 12 for TRIANGLES, 4 for INDICES).

/// How a view's bytes are compressed (the extension's `mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Mode {
    Attributes,
    Triangles,
    Indices,
}

/// What is applied to ATTRIBUTES once decoded (the extension's `filter`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
}

/// The attribute stream's header byte (version 0, the one the extension
/// allows).
const ATTRIBUTES_HEADER: u8 = 0xa0;
const TRIANGLES_HEADER: u8 = 0xe1;
const INDICES_HEADER: u8 = 0xd1;
/// The attribute stream's tail: the baseline element, padded before to at
/// least this many bytes.
const ATTRIBUTES_TAIL_MIN: usize = 32;
/// The triangle stream's tail: the 16-byte `codeaux` table.
const TRIANGLES_TAIL: usize = 16;
/// The index stream's tail: 4 reserved bytes.
const INDICES_TAIL: usize = 4;

/// Decodes `count` elements of `stride` bytes from `data`, checking the
/// combination of mode, filter and stride the extension allows.
pub(super) fn decode(
    data: &[u8],
    count: usize,
    stride: usize,
    mode: Mode,
    filter: Filter,
) -> Result<Vec<u8>, String> {
    match mode {
        Mode::Attributes => {
            if stride == 0 || !stride.is_multiple_of(4) || stride > 256 {
                return Err(format!(
                    "ATTRIBUTES byteStride {stride} is not a multiple of 4 from 4 to 256"
                ));
            }
            let filter_ok = match filter {
                Filter::None => true,
                Filter::Octahedral => stride == 4 || stride == 8,
                Filter::Quaternion => stride == 8,
                Filter::Exponential => true,
            };
            if !filter_ok {
                return Err(format!("filter {filter:?} with byteStride {stride}"));
            }
            let mut out = decode_attributes(data, count, stride)?;
            apply_filter(&mut out, stride, filter);
            Ok(out)
        }
        Mode::Triangles | Mode::Indices => {
            if stride != 2 && stride != 4 {
                return Err(format!("{mode:?} byteStride {stride} is not 2 or 4"));
            }
            if filter != Filter::None {
                return Err(format!("filter {filter:?} on {mode:?}"));
            }
            let indices = if mode == Mode::Triangles {
                decode_triangles(data, count)?
            } else {
                decode_indices(data, count)?
            };
            Ok(if stride == 2 {
                // The encoder wrote 16-bit indices: each fits, or wraps as
                // the reference decoder's store does.
                indices
                    .iter()
                    .flat_map(|&i| (i as u16).to_le_bytes())
                    .collect()
            } else {
                indices.iter().flat_map(|&i| i.to_le_bytes()).collect()
            })
        }
    }
}

/// Elements per attribute block for a stride.
fn block_elements(stride: usize) -> usize {
    ((8192 / stride) & !15).min(256)
}

/// Header bytes of one byte's data block over `elements` elements: two
/// bits per group of 16.
fn header_bytes(elements: usize) -> usize {
    elements.div_ceil(16).div_ceil(4)
}

fn decode_attributes(data: &[u8], count: usize, stride: usize) -> Result<Vec<u8>, String> {
    if data.first() != Some(&ATTRIBUTES_HEADER) {
        return Err(match data.first() {
            Some(h) if h & 0xf0 == 0xa0 => {
                format!(
                    "ATTRIBUTES stream version {} (only version 0 is read)",
                    h & 0x0f
                )
            }
            Some(h) => format!("ATTRIBUTES stream header {h:#04x}, not 0xa0"),
            None => "empty ATTRIBUTES stream".to_string(),
        });
    }
    let tail = stride.max(ATTRIBUTES_TAIL_MIN);
    // The smallest stream for `count` elements: every group's deltas zero,
    // so its header bits only.
    let per_block = block_elements(stride);
    let least = (count / per_block)
        .checked_mul(header_bytes(per_block))
        .and_then(|h| h.checked_add(header_bytes(count % per_block)))
        .and_then(|h| h.checked_mul(stride))
        .and_then(|h| h.checked_add(1 + tail));
    if least.is_none_or(|least| least > data.len()) {
        return Err(format!(
            "ATTRIBUTES stream of {} bytes is too short for {count} elements of {stride} bytes",
            data.len()
        ));
    }
    let mut last: Vec<u8> = data[data.len() - stride..].to_vec();
    let body = &data[..data.len() - tail];
    let mut at = 1;
    let mut out = vec![0u8; count * stride];
    let mut deltas = [0u8; 256];
    let mut start = 0;
    while start < count {
        let elements = (count - start).min(per_block);
        let groups = elements.div_ceil(16);
        for (k, last_k) in last.iter_mut().enumerate() {
            let header = body
                .get(at..at + header_bytes(elements))
                .ok_or("ATTRIBUTES stream ends inside a block header")?;
            at += header.len();
            for g in 0..groups {
                let bits = (header[g / 4] >> ((g % 4) * 2)) & 3;
                let group = &mut deltas[g * 16..g * 16 + 16];
                at = decode_group(body, at, bits, group)?;
            }
            for (i, delta) in deltas[..elements].iter().enumerate() {
                let value = last_k.wrapping_add(unzigzag8(*delta));
                out[(start + i) * stride + k] = value;
                *last_k = value;
            }
        }
        start += elements;
    }
    Ok(out)
}

/// One group's 16 byte deltas (still zigzagged) from `body` at `at`;
/// returns where the next group starts.
fn decode_group(body: &[u8], at: usize, bits: u8, group: &mut [u8]) -> Result<usize, String> {
    let short = || "ATTRIBUTES stream ends inside a group of deltas".to_string();
    match bits {
        0 => {
            group.fill(0);
            Ok(at)
        }
        3 => {
            group.copy_from_slice(body.get(at..at + 16).ok_or_else(short)?);
            Ok(at + 16)
        }
        _ => {
            // 2 or 4 bits a delta, the first in the high bits; the all-ones
            // value is a sentinel for a full byte after the packed deltas.
            let width = if bits == 1 { 2 } else { 4 };
            let packed = body.get(at..at + 2 * width).ok_or_else(short)?;
            let sentinel = (1u8 << width) - 1;
            let per_byte = 8 / width;
            let mut extra = at + 2 * width;
            for (i, delta) in group.iter_mut().enumerate() {
                let shift = 8 - width * (i % per_byte + 1);
                let v = (packed[i / per_byte] >> shift) & sentinel;
                *delta = if v == sentinel {
                    let b = *body.get(extra).ok_or_else(short)?;
                    extra += 1;
                    b
                } else {
                    v
                };
            }
            Ok(extra)
        }
    }
}

fn unzigzag8(v: u8) -> u8 {
    if v & 1 != 0 {
        !(v >> 1)
    } else {
        v >> 1
    }
}

/// An unsigned LEB128 value of at most 32 bits (five bytes).
fn read_varint(data: &[u8], at: &mut usize, end: usize) -> Result<u32, String> {
    let mut value = 0u32;
    for shift in (0..35).step_by(7) {
        if *at >= end {
            return Err("stream ends inside a varint".to_string());
        }
        let b = data[*at];
        *at += 1;
        value |= u32::from(b & 0x7f).wrapping_shl(shift);
        if b & 0x80 == 0 {
            return Ok(value);
        }
    }
    Err("a varint longer than five bytes".to_string())
}

fn decode_triangles(data: &[u8], count: usize) -> Result<Vec<u32>, String> {
    if !count.is_multiple_of(3) {
        return Err(format!("TRIANGLES count {count} is not a multiple of 3"));
    }
    let triangles = count / 3;
    if data.first() != Some(&TRIANGLES_HEADER) {
        return Err(format!(
            "TRIANGLES stream header {:?}, not 0xe1",
            data.first()
        ));
    }
    if triangles
        .checked_add(1 + TRIANGLES_TAIL)
        .is_none_or(|least| least > data.len())
    {
        return Err(format!(
            "TRIANGLES stream of {} bytes is too short for {triangles} triangles",
            data.len()
        ));
    }
    let end = data.len() - TRIANGLES_TAIL;
    let mut decoder = TriangleDecoder {
        data,
        end,
        at: 1 + triangles,
        edges: Ring::default(),
        vertices: Ring::default(),
        next: 0,
        last: 0,
    };
    let mut out = Vec::with_capacity(count);
    for &code in &data[1..1 + triangles] {
        let (x, y) = (usize::from(code >> 4), code & 15);
        let triangle = if x < 15 {
            decoder.on_edge(x, y)?
        } else {
            decoder.free(y, &data[end..])?
        };
        out.extend_from_slice(&triangle);
    }
    if decoder.at != end {
        return Err(format!(
            "TRIANGLES stream has {} bytes of extra data left over",
            end - decoder.at
        ));
    }
    Ok(out)
}

/// The state of a TRIANGLES stream's decoding (the extension's appendix):
/// its extra data read from `at` up to `end`, the edge and vertex FIFOs,
/// the next new vertex and the last explicit one.
struct TriangleDecoder<'a> {
    data: &'a [u8],
    end: usize,
    at: usize,
    edges: Ring<(u32, u32)>,
    vertices: Ring<u32>,
    next: u32,
    last: u32,
}

impl TriangleDecoder<'_> {
    /// The next new vertex.
    fn take_next(&mut self) -> u32 {
        self.next = self.next.wrapping_add(1);
        self.next.wrapping_sub(1)
    }

    /// A zigzagged delta from the last explicit vertex, read as a varint.
    fn explicit(&mut self) -> Result<u32, String> {
        let v = read_varint(self.data, &mut self.at, self.end)?;
        let delta = if v & 1 != 0 { !(v >> 1) } else { v >> 1 };
        self.last = self.last.wrapping_add(delta);
        Ok(self.last)
    }

    /// Code 0xXY, X < 15: a triangle on edge X of the FIFO, its third
    /// vertex by Y (new, from the vertex FIFO, the last explicit one -1,
    /// +1, or explicit).
    fn on_edge(&mut self, x: usize, y: u8) -> Result<[u32; 3], String> {
        let (a, b) = self.edges.back(x);
        let c = match y {
            0 => self.take_next(),
            1..=12 => self.vertices.back(usize::from(y)),
            13 => {
                self.last = self.last.wrapping_sub(1);
                self.last
            }
            14 => {
                self.last = self.last.wrapping_add(1);
                self.last
            }
            _ => self.explicit()?,
        };
        self.edges.push((c, b));
        self.edges.push((a, c));
        if !(1..=12).contains(&y) {
            self.vertices.push(c);
        }
        Ok([a, b, c])
    }

    /// Code 0xfY: a triangle on no edge. Y < 14 takes its two other
    /// vertices' nibbles from the stream's table (`codeaux`); 0xfe and 0xff
    /// from a data byte (0 restarts the new vertices), its first vertex new
    /// or explicit.
    fn free(&mut self, y: u8, codeaux: &[u8]) -> Result<[u32; 3], String> {
        let (zw, a) = if y < 14 {
            (codeaux[usize::from(y)], self.take_next())
        } else {
            let zw = *self
                .data
                .get(self.at)
                .filter(|_| self.at < self.end)
                .ok_or("TRIANGLES stream ends inside its extra data")?;
            self.at += 1;
            if zw == 0 {
                self.next = 0;
            }
            let a = if y == 14 {
                self.take_next()
            } else {
                self.explicit()?
            };
            (zw, a)
        };
        let explicit_allowed = y >= 14;
        let (z, w) = (zw >> 4, zw & 15);
        let mut corner = |n: u8| -> Result<u32, String> {
            Ok(match n {
                0 => self.take_next(),
                15 if explicit_allowed => self.explicit()?,
                _ => self.vertices.back(usize::from(n - 1)),
            })
        };
        let b = corner(z)?;
        let c = corner(w)?;
        self.edges.push((b, a));
        self.edges.push((c, b));
        self.edges.push((a, c));
        self.vertices.push(a);
        let pushed = |n: u8| n == 0 || (explicit_allowed && n == 15);
        if pushed(z) {
            self.vertices.push(b);
        }
        if pushed(w) {
            self.vertices.push(c);
        }
        Ok([a, b, c])
    }
}

/// A 16-entry FIFO; entries never written read as the default.
#[derive(Default)]
struct Ring<T: Copy + Default> {
    items: [T; 16],
    pushed: usize,
}

impl<T: Copy + Default> Ring<T> {
    fn push(&mut self, item: T) {
        self.items[self.pushed & 15] = item;
        self.pushed = self.pushed.wrapping_add(1);
    }

    /// The entry `back` places before the most recent (0: the most recent).
    fn back(&self, back: usize) -> T {
        self.items[self.pushed.wrapping_sub(1 + back) & 15]
    }
}

fn decode_indices(data: &[u8], count: usize) -> Result<Vec<u32>, String> {
    if data.first() != Some(&INDICES_HEADER) {
        return Err(format!(
            "INDICES stream header {:?}, not 0xd1",
            data.first()
        ));
    }
    if count
        .checked_add(1 + INDICES_TAIL)
        .is_none_or(|least| least > data.len())
    {
        return Err(format!(
            "INDICES stream of {} bytes is too short for {count} indices",
            data.len()
        ));
    }
    let end = data.len() - INDICES_TAIL;
    let mut at = 1;
    let mut last = [0u32; 2];
    let mut out = Vec::with_capacity(count);
    for _ in 0..count {
        let v = read_varint(data, &mut at, end)?;
        let baseline = (v & 1) as usize;
        let delta = if v & 2 != 0 { !(v >> 2) } else { v >> 2 };
        last[baseline] = last[baseline].wrapping_add(delta);
        out.push(last[baseline]);
    }
    if at != end {
        return Err(format!("INDICES stream has {} bytes left over", end - at));
    }
    Ok(out)
}

/// The filters, in place on decoded elements of `stride` bytes. Values
/// outside the ranges the extension allows give unspecified (but finite or
/// saturated, never panicking) results, as it permits.
fn apply_filter(out: &mut [u8], stride: usize, filter: Filter) {
    match filter {
        Filter::None => {}
        Filter::Octahedral if stride == 4 => {
            for e in out.chunks_exact_mut(4) {
                let v = octahedral([e[0], e[1], e[2]].map(|b| f32::from(b as i8)), 127.0);
                for (o, x) in e.iter_mut().zip(v) {
                    *o = (x as i8) as u8;
                }
            }
        }
        Filter::Octahedral => {
            for e in out.chunks_exact_mut(8) {
                let input = [0, 2, 4].map(|i| f32::from(i16::from_le_bytes([e[i], e[i + 1]])));
                let v = octahedral(input, 32767.0);
                for (i, x) in v.into_iter().enumerate() {
                    e[2 * i..2 * i + 2].copy_from_slice(&(x as i16).to_le_bytes());
                }
            }
        }
        Filter::Quaternion => {
            for e in out.chunks_exact_mut(8) {
                let q = [0, 2, 4, 6].map(|i| i16::from_le_bytes([e[i], e[i + 1]]));
                let range = std::f32::consts::FRAC_1_SQRT_2;
                let one = f32::from(q[3] | 3);
                let [x, y, z] = [q[0], q[1], q[2]].map(|c| f32::from(c) / one * range);
                let w = (1.0 - x * x - y * y - z * z).max(0.0).sqrt();
                let max = (q[3] & 3) as usize;
                for (k, v) in [(1, x), (2, y), (3, z), (0, w)] {
                    let value = (v * 32767.0).round() as i16;
                    let i = (max + k) % 4;
                    e[2 * i..2 * i + 2].copy_from_slice(&value.to_le_bytes());
                }
            }
        }
        Filter::Exponential => {
            for e in out.chunks_exact_mut(4) {
                let input = i32::from_le_bytes([e[0], e[1], e[2], e[3]]);
                let exponent = input >> 24;
                let mantissa = (input << 8) >> 8;
                let value = 2f32.powi(exponent) * mantissa as f32;
                e.copy_from_slice(&value.to_le_bytes());
            }
        }
    }
}

/// A unit vector from its octahedral x, y and K-bit one, as integers of
/// `max` (127 or 32767); rounded half away from zero.
fn octahedral([x, y, one]: [f32; 3], max: f32) -> [f32; 3] {
    let (mut x, mut y) = (x / one, y / one);
    let z = 1.0 - x.abs() - y.abs();
    let t = z.min(0.0);
    x -= t.copysign(x);
    y -= t.copysign(y);
    let length = (x * x + y * y + z * z).sqrt();
    [x, y, z].map(|c| (c / length * max).round())
}

#[cfg(test)]
#[path = "meshopt_tests.rs"]
mod tests;
