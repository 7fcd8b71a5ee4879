//! Which vector instructions the code may use, found at run time so that
//! one binary runs on any x86-64 and uses what the CPU has.

/// The widest code path allowed: `VREF_SIMD=baseline` or `avx2` caps it
/// (to time or check the narrower paths on a CPU that has more); unset or
/// anything else allows what the CPU has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Cap {
    Baseline,
    Avx2,
    Avx512,
}

fn cap() -> Cap {
    static CAP: std::sync::OnceLock<Cap> = std::sync::OnceLock::new();
    *CAP.get_or_init(|| match std::env::var("VREF_SIMD").as_deref() {
        Ok("baseline") => Cap::Baseline,
        Ok("avx2") => Cap::Avx2,
        _ => Cap::Avx512,
    })
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
