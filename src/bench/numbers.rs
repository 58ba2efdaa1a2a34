//! How the bench's outputs write numbers: optional values, milliseconds to
//! about three significant digits, counts with thousands separators and
//! ratios.

/// An optional value, or nothing.
pub fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

/// An optional value with `decimals` decimals, or nothing.
pub fn opt_f(v: Option<f64>, decimals: usize) -> String {
    v.map_or(String::new(), |v| format!("{v:.decimals$}"))
}

/// Milliseconds with about 3 significant digits.
pub fn ms(v: Option<f64>) -> String {
    match v {
        None => "-".into(),
        Some(v) if v >= 100.0 => format!("{v:.0}"),
        Some(v) if v >= 10.0 => format!("{v:.1}"),
        Some(v) => format!("{v:.2}"),
    }
}

/// `1234567` as `1,234,567`.
pub fn count(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A ratio with 3 significant digits down to 0.001 (`12.3x`, `1.23x`, `0.0412x`).
pub fn ratio_text(v: f64) -> String {
    if v >= 10.0 {
        format!("{v:.1}x")
    } else if v >= 1.0 {
        format!("{v:.2}x")
    } else if v >= 0.1 {
        format!("{v:.3}x")
    } else {
        format!("{v:.4}x")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_get_thousands_separators() {
        assert_eq!(count(0), "0");
        assert_eq!(count(999), "999");
        assert_eq!(count(1000), "1,000");
        assert_eq!(count(1234567), "1,234,567");
    }
}
