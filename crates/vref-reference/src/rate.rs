//! Each client's share of the matcher: a token bucket per client port, so
//! a client that sends without pause is answered at its rate and the rest
//! of its queries cost a receive, not an answer and a wake-up of every
//! client.

use std::time::Instant;

/// A client: iceoryx2's unique client port id.
pub type Client = u128;

#[derive(Debug, Clone, Copy)]
struct Bucket {
    client: Client,
    tokens: f64,
    at: Instant,
}

/// Token buckets for up to a fixed number of clients, allocated once.
#[derive(Debug, Clone)]
pub struct QueryRate {
    per_second: f64,
    burst: f64,
    buckets: Vec<Bucket>,
    capacity: usize,
}

impl QueryRate {
    /// `per_second` queries per client, bursts of a tenth of a second's
    /// worth (at least 10); room for `clients` buckets.
    pub fn new(per_second: f64, clients: usize) -> Self {
        let capacity = clients.max(1);
        Self {
            per_second,
            burst: (per_second / 10.0).max(10.0),
            buckets: Vec::with_capacity(capacity),
            capacity,
        }
    }

    /// Whether `client` may be answered now (taking a token if so). Makes
    /// no allocation: this runs on the query path.
    pub fn allow(&mut self, client: Client, now: Instant) -> bool {
        let index = match self.buckets.iter().position(|b| b.client == client) {
            Some(k) => k,
            None => self.admit(client, now),
        };
        let bucket = &mut self.buckets[index];
        let refill = now.saturating_duration_since(bucket.at).as_secs_f64() * self.per_second;
        bucket.tokens = (bucket.tokens + refill).min(self.burst);
        bucket.at = now;
        if bucket.tokens >= 1.0 {
            bucket.tokens -= 1.0;
            true
        } else {
            false
        }
    }

    /// A full bucket for a new client, in a free place or in place of the
    /// one heard from least recently (within capacity, never growing).
    fn admit(&mut self, client: Client, now: Instant) -> usize {
        let fresh = Bucket {
            client,
            tokens: self.burst,
            at: now,
        };
        if self.buckets.len() < self.capacity {
            self.buckets.push(fresh);
            return self.buckets.len() - 1;
        }
        let oldest = (0..self.buckets.len())
            .min_by_key(|&k| self.buckets[k].at)
            .unwrap_or(0);
        self.buckets[oldest] = fresh;
        oldest
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn a_client_gets_its_burst_then_its_rate_and_others_are_unaffected() {
        let t = Instant::now();
        let mut rate = QueryRate::new(1000.0, 4);
        let allowed = (0..1000).filter(|_| rate.allow(1, t)).count();
        assert_eq!(allowed, 100, "a tenth of a second's worth at once");
        assert!(rate.allow(2, t), "another client has its own bucket");
        let later = t + Duration::from_millis(50);
        let allowed = (0..1000).filter(|_| rate.allow(1, later)).count();
        assert_eq!(allowed, 50);
    }

    #[test]
    fn more_clients_than_room_replace_the_quietest() {
        let t = Instant::now();
        let mut rate = QueryRate::new(100.0, 2);
        for k in 0..10 {
            assert!(rate.allow(k, t + Duration::from_millis(k as u64)));
        }
        assert_eq!(rate.buckets.len(), 2);
    }
}
