//! The statements and tokens both OBJ and MTL lines are made of, read the
//! same way by the reference parser, the fast path's chunks and the MTL
//! reader: a text's statements (line, keyword, tokens), comments, the rest
//! of a line after its keyword, finite numbers, and the error naming a
//! statement.

use std::path::Path;
use std::str::SplitAsciiWhitespace;

use crate::scene::error::SceneError;

/// The statements of `text` in order, past a leading byte-order mark, each
/// as (1-based line number, the line without its comment, its keyword, the
/// tokens after the keyword); blank and comment-only lines are skipped.
pub(super) fn statements(
    text: &str,
) -> impl Iterator<Item = (usize, &str, &str, SplitAsciiWhitespace<'_>)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    text.split('\n').enumerate().filter_map(|(number, raw)| {
        let line = strip_comment(raw);
        let mut tokens = line.split_ascii_whitespace();
        let keyword = tokens.next()?;
        Some((number + 1, line, keyword, tokens))
    })
}

/// Makes the error of the statement `keyword` on line `line_no` of `path`
/// from its message.
pub(super) fn statement_error<'a>(
    path: &'a Path,
    line_no: usize,
    keyword: &'a str,
) -> impl Fn(String) -> SceneError + Copy + 'a {
    move |message| SceneError::new(path, Some(line_no), Some(keyword.to_string()), message)
}

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

/// The first three of `tokens` as numbers (0 past the last) and how many
/// tokens there are; every token must be a number, the first that is not is
/// the error.
pub(super) fn first_three_numbers<'t>(
    tokens: impl Iterator<Item = &'t str>,
) -> Result<([f64; 3], usize), String> {
    let mut values = [0.0f64; 3];
    let mut count = 0usize;
    for token in tokens {
        let value = parse_number(token)?;
        if count < 3 {
            values[count] = value;
        }
        count += 1;
    }
    Ok((values, count))
}
