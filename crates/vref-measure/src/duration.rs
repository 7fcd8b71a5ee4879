//! The one way a duration is written on vref's command lines: a positive
//! number with a unit, `500ms`, `10s`, `1.5s`, `2m`, `1h`. A bare number
//! is refused (is `5` seconds or milliseconds?), and so is zero.

use std::time::Duration;

/// Why text is not a duration.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DurationError {
    #[error("`{0}` is not a duration (examples: 10s, 500ms, 2m)")]
    NotANumber(String),
    #[error("`{0}` has no unit: write e.g. {0}s or {0}ms")]
    NoUnit(String),
    #[error("unknown unit `{unit}` in `{text}` (use ms, s, m or h)")]
    UnknownUnit { unit: String, text: String },
    #[error("`{0}` must be a positive duration under 100 days")]
    OutOfRange(String),
}

/// Parses `10s`, `500ms`, `2m`, `1h` (decimals allowed: `1.5s`).
pub fn parse_duration(text: &str) -> Result<Duration, DurationError> {
    let text = text.trim();
    let split = text
        .find(|c: char| c.is_ascii_alphabetic())
        .unwrap_or(text.len());
    let (number, unit) = text.split_at(split);
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| DurationError::NotANumber(text.to_owned()))?;
    let seconds = match unit {
        "" => return Err(DurationError::NoUnit(text.to_owned())),
        "ms" => value / 1000.0,
        "s" => value,
        "m" | "min" => value * 60.0,
        "h" => value * 3600.0,
        other => {
            return Err(DurationError::UnknownUnit {
                unit: other.to_owned(),
                text: text.to_owned(),
            });
        }
    };
    if !(seconds.is_finite() && seconds > 0.0 && seconds < 8.64e6) {
        return Err(DurationError::OutOfRange(text.to_owned()));
    }
    Ok(Duration::from_secs_f64(seconds))
}

/// A duration as [`parse_duration`] reads it back: whole seconds as `10s`,
/// anything else in milliseconds (`500ms`, `1500ms`, `0.25ms`).
pub fn format_duration(d: Duration) -> String {
    if d.subsec_nanos() == 0 {
        format!("{}s", d.as_secs())
    } else {
        let ms = d.as_secs_f64() * 1000.0;
        format!("{}ms", (ms * 1000.0).round() / 1000.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn good_inputs() {
        assert_eq!(parse_duration("10s"), Ok(Duration::from_secs(10)));
        assert_eq!(parse_duration("500ms"), Ok(Duration::from_millis(500)));
        assert_eq!(parse_duration("1.5s"), Ok(Duration::from_millis(1500)));
        assert_eq!(parse_duration("2m"), Ok(Duration::from_secs(120)));
        assert_eq!(parse_duration("2min"), Ok(Duration::from_secs(120)));
        assert_eq!(parse_duration("1h"), Ok(Duration::from_secs(3600)));
        assert_eq!(parse_duration(" 200ms "), Ok(Duration::from_millis(200)));
    }

    #[test]
    fn bad_inputs_say_what_is_wrong() {
        assert_eq!(
            parse_duration("5"),
            Err(DurationError::NoUnit("5".to_owned()))
        );
        assert!(parse_duration("5").is_err_and(|e| e.to_string().contains("5s or 5ms")));
        assert!(matches!(
            parse_duration("ten"),
            Err(DurationError::NotANumber(_))
        ));
        assert!(matches!(
            parse_duration("soon"),
            Err(DurationError::NotANumber(_))
        ));
        assert!(matches!(
            parse_duration("5 parsecs"),
            Err(DurationError::UnknownUnit { .. })
        ));
        assert!(matches!(
            parse_duration("0s"),
            Err(DurationError::OutOfRange(_))
        ));
        assert!(matches!(
            parse_duration("-1s"),
            Err(DurationError::OutOfRange(_))
        ));
        assert!(matches!(
            parse_duration("3000h"),
            Err(DurationError::OutOfRange(_))
        ));
        assert!(parse_duration("").is_err());
    }

    #[test]
    fn formatted_durations_read_back() {
        for d in [
            Duration::from_secs(10),
            Duration::from_millis(500),
            Duration::from_millis(1500),
        ] {
            assert_eq!(parse_duration(&format_duration(d)), Ok(d));
        }
        assert_eq!(format_duration(Duration::from_millis(250)), "250ms");
        assert_eq!(format_duration(Duration::from_secs(30)), "30s");
    }
}
