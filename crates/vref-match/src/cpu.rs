//! Which vector instructions the code may use, found at run time so that
//! one binary runs on any x86-64 and uses what the CPU has.

/// The widest code path allowed: `VREF_SIMD=baseline`, `avx2` or `avx512`
/// caps it (to time or check the narrower paths on a CPU that has more);
/// unset allows what the CPU has. Any other value allows only the
/// baseline, and [`check_simd_setting`] names it, so that a misspelt cap
/// is refused by the programs instead of silently meaning "everything".
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Cap {
    Baseline,
    Avx2,
    Avx512,
}

/// `VREF_SIMD` names no code path.
#[derive(Debug, thiserror::Error)]
#[error("VREF_SIMD={0:?} is not a code path: use baseline, avx2 or avx512, or leave it unset")]
pub struct UnknownSimd(pub String);

fn parse(value: Option<&str>) -> Result<Cap, UnknownSimd> {
    match value {
        None | Some("avx512") => Ok(Cap::Avx512),
        Some("avx2") => Ok(Cap::Avx2),
        Some("baseline") => Ok(Cap::Baseline),
        Some(other) => Err(UnknownSimd(other.to_owned())),
    }
}

fn setting() -> Option<String> {
    std::env::var_os("VREF_SIMD").map(|v| v.to_string_lossy().into_owned())
}

fn cap() -> Cap {
    static CAP: std::sync::OnceLock<Cap> = std::sync::OnceLock::new();
    *CAP.get_or_init(|| parse(setting().as_deref()).unwrap_or(Cap::Baseline))
}

/// Whether `VREF_SIMD` is unset or names a code path; programs check it
/// at start.
pub fn check_simd_setting() -> Result<(), UnknownSimd> {
    parse(setting().as_deref()).map(|_| ())
}

/// Whether AVX2 and FMA may be used.
pub(crate) fn avx2_fma() -> bool {
    // std caches the answer: this is an atomic load after the first.
    cap() >= Cap::Avx2 && is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")
}

/// Whether AVX-512F (with AVX2 and FMA) may be used.
pub(crate) fn avx512() -> bool {
    cap() >= Cap::Avx512 && avx2_fma() && is_x86_feature_detected!("avx512f")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_path_parses_and_others_are_refused() {
        assert_eq!(parse(None).unwrap(), Cap::Avx512);
        assert_eq!(parse(Some("avx512")).unwrap(), Cap::Avx512);
        assert_eq!(parse(Some("avx2")).unwrap(), Cap::Avx2);
        assert_eq!(parse(Some("baseline")).unwrap(), Cap::Baseline);
        for bad in ["", "AVX2", "avx-512", "sse"] {
            let e = parse(Some(bad)).unwrap_err();
            assert!(e.to_string().contains("baseline, avx2 or avx512"), "{e}");
        }
    }
}
