//! The one way a direction is written on vref's command lines: three
//! finite numbers, `X,Y,Z`, not all zero (`0,0,1`). Its length does not
//! matter; whoever uses it makes it unit.

/// Why text is not a direction.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DirectionError {
    #[error("`{0}` is not a direction: expected X,Y,Z (e.g. 0,0,1)")]
    NotThree(String),
    #[error("`{number}` in `{text}` is not a finite number")]
    NotANumber { number: String, text: String },
    #[error("a direction cannot be 0,0,0")]
    Zero,
}

/// Parses `X,Y,Z` (spaces around each number allowed).
pub fn parse_direction(text: &str) -> Result<[f64; 3], DirectionError> {
    let parts: Vec<&str> = text.split(',').collect();
    let [x, y, z] = parts.as_slice() else {
        return Err(DirectionError::NotThree(text.to_owned()));
    };
    let number = |p: &str| {
        p.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| DirectionError::NotANumber {
                number: p.trim().to_owned(),
                text: text.to_owned(),
            })
    };
    let v = [number(x)?, number(y)?, number(z)?];
    if v.iter().all(|&c| c == 0.0) {
        return Err(DirectionError::Zero);
    }
    Ok(v)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn three_numbers_are_a_direction_and_anything_else_is_named() {
        assert_eq!(parse_direction("0, 0,1").unwrap(), [0.0, 0.0, 1.0]);
        assert_eq!(parse_direction("-0.5,2,1e-3").unwrap(), [-0.5, 2.0, 1e-3]);
        assert_eq!(
            parse_direction("0,1"),
            Err(DirectionError::NotThree("0,1".to_owned()))
        );
        assert!(matches!(
            parse_direction("0,up,1"),
            Err(DirectionError::NotANumber { number, .. }) if number == "up"
        ));
        assert!(matches!(
            parse_direction("0,NaN,1"),
            Err(DirectionError::NotANumber { .. })
        ));
        assert_eq!(parse_direction("0,0,0"), Err(DirectionError::Zero));
    }
}
