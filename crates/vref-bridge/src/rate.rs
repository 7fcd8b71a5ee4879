use std::time::{Duration, Instant};

/// A token bucket: at most `rate` messages per second on average, and a
/// burst of a quarter second's worth (at least 2), so that a headset
/// catching up after a Wi-Fi stall is not cut off while a flood is.
#[derive(Debug, Clone)]
pub struct RateLimit {
    rate_hz: f64,
    burst: f64,
    tokens: f64,
    last: Option<Instant>,
}

impl RateLimit {
    /// `rate_hz` must be positive and finite (the configuration checks it).
    pub fn new(rate_hz: f64) -> Self {
        let burst = (rate_hz / 4.0).ceil().max(2.0);
        Self {
            rate_hz,
            burst,
            tokens: burst,
            last: None,
        }
    }

    /// Whether a message arriving at `now` is within the rate; if so it
    /// spends a token.
    pub fn admit(&mut self, now: Instant) -> bool {
        if let Some(last) = self.last {
            let elapsed = now.saturating_duration_since(last).as_secs_f64();
            self.tokens = (self.tokens + elapsed * self.rate_hz).min(self.burst);
        }
        self.last = Some(now);
        if self.tokens >= 1.0 {
            self.tokens -= 1.0;
            true
        } else {
            false
        }
    }

    /// The burst size, messages.
    pub fn burst(&self) -> u64 {
        self.burst as u64
    }

    /// The time one token takes to come back.
    pub fn period(&self) -> Duration {
        Duration::from_secs_f64(1.0 / self.rate_hz)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flood_gets_the_burst_then_the_rate() {
        let mut limit = RateLimit::new(40.0);
        assert_eq!(limit.burst(), 10);
        let t0 = Instant::now();
        // 1000 messages within one millisecond: only the burst passes.
        let passed = (0..1000)
            .filter(|i| limit.admit(t0 + Duration::from_nanos(*i)))
            .count();
        assert_eq!(passed, 10);
        // Then one second at 1 kHz: the rate's 40 more (and no burst saved
        // up), give or take the rounding of the last token.
        let passed = (1..=1000)
            .filter(|ms| limit.admit(t0 + Duration::from_millis(*ms)))
            .count();
        assert!((39..=40).contains(&passed), "{passed}");
    }

    #[test]
    fn traffic_at_the_rate_all_passes() {
        let mut limit = RateLimit::new(30.0);
        let t0 = Instant::now();
        let period = limit.period();
        assert!((0..300).all(|i| limit.admit(t0 + period * i)));
    }
}
