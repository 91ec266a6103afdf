//! What a robot can produce: the bounds every importer holds values to, and the escaping of
//! text from a file before it goes into a message.
//!
//! A value outside these bounds comes from a broken or hostile file, not from a robot, and is
//! refused with its place (docs/formats.md, importers): no building is larger than
//! [`MAX_LENGTH_M`], no recording runs past [`MAX_TIME_S`], and no odometry turns more than
//! [`MAX_HEADING_RAD`] (an unwrapped heading of some 16,000 turns).

use std::fmt::Write;

/// The largest coordinate, mount offset, range or robot radius, metres (10 km).
pub const MAX_LENGTH_M: f64 = 10_000.0;

/// The largest time magnitude, seconds: 1e10 s after 1970 is the year 2286, beyond any
/// recording's clock (ROS stamps and Unix times are about 1.7e9 s).
pub const MAX_TIME_S: f64 = 1e10;

/// The largest heading or yaw magnitude, radians (about 16,000 turns).
pub const MAX_HEADING_RAD: f64 = 1e5;

/// The narrowest beam, degrees: a beam width (or ROS field of view) between 0 and this is
/// no sonar's (and would be written as 0, which the log format refuses).
pub const MIN_BEAM_DEG: f64 = 0.01;

/// The shortest maximum range, metres (1 mm).
pub const MIN_MAX_RANGE_M: f64 = 1e-3;

/// The smallest accuracy, percent of range.
pub const MIN_ACCURACY_PCT: f64 = 1e-3;

/// The log loader's bounds are this factor wider than the importers' (a value at an
/// importer's bound, converted to the log's unit and rounded, still loads).
pub const LOADER_SLACK: f64 = 1.0 + 1e-6;

/// The largest number of characters of file text quoted in a message.
pub const QUOTE_CHARS: usize = 60;

/// Checks `v` is finite and at most `limit` in magnitude. The error says what was found and
/// what was expected (`what`, `unit` is the unit `v` and `limit` are written in).
pub fn within(v: f64, limit: f64, what: &str, unit: &str) -> Result<f64, String> {
    if !v.is_finite() {
        return Err(format!(
            "{} is not a finite number: expected {what}",
            show(v)
        ));
    }
    if v.abs() > limit {
        return Err(format!(
            "{} is beyond ±{} {unit}: expected {what} that a robot can produce",
            show(v),
            fmt_limit(limit)
        ));
    }
    Ok(v)
}

/// A number for a message: as Rust writes it, but in exponent form when that is shorter
/// (`1e308`, not 309 digits).
pub fn show(v: f64) -> String {
    let plain = v.to_string();
    let exp = format!("{v:e}");
    if exp.len() < plain.len() {
        exp
    } else {
        plain
    }
}

/// A limit as a short number (`10000`, `393700.79`).
fn fmt_limit(limit: f64) -> String {
    if limit >= 1e7 {
        format!("{limit:e}")
    } else {
        let s = format!("{limit:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// A time in seconds within ±[`MAX_TIME_S`].
pub fn time(t: f64, what: &str) -> Result<f64, String> {
    within(t, MAX_TIME_S, what, "s")
}

/// A length, written in a unit of `metres_per_unit` metres, within ±[`MAX_LENGTH_M`].
pub fn length(v: f64, metres_per_unit: f64, what: &str, unit: &str) -> Result<f64, String> {
    within(v, MAX_LENGTH_M / metres_per_unit, what, unit)
}

/// A heading in radians within ±[`MAX_HEADING_RAD`].
pub fn heading_rad(a: f64, what: &str) -> Result<f64, String> {
    within(a, MAX_HEADING_RAD, what, "rad")
}

/// A heading in degrees within ±[`MAX_HEADING_RAD`] (in degrees).
pub fn heading_deg(a: f64, what: &str) -> Result<f64, String> {
    within(a, MAX_HEADING_RAD.to_degrees(), what, "°")
}

/// `text` with every control character escaped (`\u{1b}`, `\n`, `\t`), so that text from a
/// file cannot move the cursor, clear the screen or forge lines of output.
pub fn escape(text: &str) -> String {
    if !text.chars().any(char::is_control) {
        return text.to_string();
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        push_escaped(&mut out, c);
    }
    out
}

fn push_escaped(out: &mut String, c: char) {
    match c {
        '\n' => out.push_str("\\n"),
        '\r' => out.push_str("\\r"),
        '\t' => out.push_str("\\t"),
        c if c.is_control() => {
            let _ = write!(out, "\\u{{{:x}}}", c as u32);
        }
        c => out.push(c),
    }
}

/// At most [`QUOTE_CHARS`] characters of `text`, control characters escaped, `...` and the
/// full length when cut: for quoting names from a file (topics, frame ids, fields).
pub fn quote(text: &str) -> String {
    let mut out = String::new();
    let mut chars = text.chars();
    for c in chars.by_ref().take(QUOTE_CHARS) {
        push_escaped(&mut out, c);
    }
    if chars.next().is_some() {
        let _ = write!(out, "... ({} bytes)", text.len());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_and_quote_control_characters() {
        assert_eq!(escape("sonar_3\u{1b}[2J"), "sonar_3\\u{1b}[2J");
        assert_eq!(escape("a\nb\u{7f}"), "a\\nb\\u{7f}");
        assert_eq!(escape("plain"), "plain");
        let long = "x".repeat(1000);
        assert_eq!(quote(&long), format!("{}... (1000 bytes)", "x".repeat(60)));
        assert_eq!(quote("\u{1b}c"), "\\u{1b}c");
    }

    #[test]
    fn bounds() {
        assert!(within(f64::NAN, 1.0, "x", "m")
            .unwrap_err()
            .contains("finite"));
        assert!(within(1e308, 1e4, "x", "m")
            .unwrap_err()
            .contains("beyond ±10000 m"));
        assert_eq!(within(-3.0, 1e4, "x", "m"), Ok(-3.0));
        assert!(time(1e300, "t").is_err());
        assert!(heading_deg(1e308, "h").is_err());
        assert!(length(1e5, 0.0254, "x", "in").is_ok());
        assert!(length(1e6, 0.0254, "x", "in").is_err());
    }
}
