/// Ticks at a fixed rate aligned to an epoch: tick `k` is due `k / rate`
/// seconds after it. Processes given the same epoch and rate tick at the
/// same times and number their ticks alike.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Ticker {
    epoch_ns: u64,
    rate_hz: f64,
    last: Option<i64>,
}

/// One tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tick {
    pub index: i64,
    /// Seconds since the epoch.
    pub t: f64,
    pub at_ns: u64,
}

impl Ticker {
    /// `rate_hz` is checked positive and finite by the caller.
    pub(crate) fn new(epoch_ns: u64, rate_hz: f64) -> Self {
        Self {
            epoch_ns,
            rate_hz,
            last: None,
        }
    }

    /// Starts the count at the first tick due at or after `now_ns`, unless
    /// started already.
    pub(crate) fn start(&mut self, now_ns: u64) {
        if self.last.is_none() {
            let first = (self.ticks_at(now_ns).ceil() as i64).saturating_sub(1);
            self.last = Some(first);
        }
    }

    /// The tick after the last one taken (the first tick due at or after
    /// `now_ns` if not started); a feed that fell more than a tick behind
    /// skips to the latest tick due instead of bursting.
    pub(crate) fn peek(&self, now_ns: u64) -> Tick {
        let ticks = self.ticks_at(now_ns);
        // Saturating casts: absurd clocks give absurd but harmless ticks.
        let index = match self.last {
            Some(last) => last.saturating_add(1).max(ticks.floor() as i64),
            None => ticks.ceil() as i64,
        };
        let t = index as f64 / self.rate_hz;
        let at = i128::from(self.epoch_ns) + (t * 1e9).round() as i128;
        Tick {
            index,
            t,
            at_ns: u64::try_from(at.max(0)).unwrap_or(u64::MAX),
        }
    }

    /// Ticks (fractional) from the epoch to `now_ns`.
    fn ticks_at(&self, now_ns: u64) -> f64 {
        let since = (i128::from(now_ns) - i128::from(self.epoch_ns)) as f64 / 1e9;
        since * self.rate_hz
    }

    pub(crate) fn take(&mut self, tick: Tick) {
        self.last = Some(tick.index);
    }
}
