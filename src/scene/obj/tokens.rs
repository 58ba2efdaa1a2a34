//! The tokens both OBJ and MTL lines are made of, read the same way by the
//! reference parser, the fast path's chunks and the MTL reader: comments,
//! the rest of a line after its keyword, finite numbers.

/// The line without its `\r` and anything from `#` on.
pub(super) fn strip_comment(line: &str) -> &str {
    let line = line.strip_suffix('\r').unwrap_or(line);
    match line.find('#') {
        Some(at) => &line[..at],
        None => line,
    }
}

/// Everything after the keyword (the line's first token), trimmed: names may
/// contain spaces.
pub(super) fn rest_of_line<'a>(line: &'a str, keyword: &str) -> &'a str {
    let line = line.trim_start_matches(|c: char| c.is_ascii_whitespace());
    line.get(keyword.len()..).unwrap_or("").trim()
}

/// A finite f64.
pub(super) fn parse_number(token: &str) -> Result<f64, String> {
    match token.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        Ok(_) => Err(format!("'{token}' is not a finite number")),
        Err(_) => Err(format!("'{token}' is not a number")),
    }
}
