//! Small vector helpers shared by the iterative methods.

pub(super) fn uniform(len: usize) -> Vec<f64> {
    vec![1.0 / len as f64; len]
}

pub(super) fn sum(v: &[f64]) -> f64 {
    v.iter().sum()
}

pub(super) fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

/// Divides by the sum when it is positive (RRWM.m leaves a zero vector).
pub(super) fn normalize_sum(v: &mut [f64]) {
    let s = sum(v);
    if s > 0.0 {
        v.iter_mut().for_each(|x| *x /= s);
    }
}

pub(super) fn squared_distance(u: &[f64], v: &[f64]) -> f64 {
    u.iter().zip(v).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// `exp(scale * v / max(v))` in place: the amplification step shared by
/// RRWM and the paper. A vector with no positive entry becomes all ones
/// (nothing to amplify).
pub(super) fn amplify(v: &mut [f64], scale: f64) {
    let top = max(v);
    let factor = if top > 0.0 { scale / top } else { 0.0 };
    v.iter_mut().for_each(|x| *x = (factor * *x).exp());
}
