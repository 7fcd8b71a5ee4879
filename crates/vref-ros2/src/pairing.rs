//! Colour, depth and (optionally) label images arrive as separate
//! messages, each on its own schedule; one frame is the three whose
//! header stamps agree within a tolerance. Each stream keeps a few recent
//! images, so that one arriving late still finds its partners, and a
//! stamp going backwards on a stream is refused (a restarted or replayed
//! source shows up as that, and mixing its images with newer ones would
//! pair things never seen together).

use std::collections::VecDeque;

use crate::decode::{DecodeError, Stream};

/// Images kept per stream while waiting for partners.
pub const KEEP: usize = 4;

/// Three images with agreeing stamps.
#[derive(Debug, Clone, PartialEq)]
pub struct Paired<C, D, L> {
    /// The colour image's stamp: the frame's capture time.
    pub stamp_ns: u64,
    pub colour: C,
    pub depth: D,
    pub labels: Option<L>,
}

/// Waiting images of each stream, oldest first.
#[derive(Debug)]
pub struct Pairer<C, D, L> {
    tolerance_ns: u64,
    want_labels: bool,
    colour: VecDeque<(u64, C)>,
    depth: VecDeque<(u64, D)>,
    labels: VecDeque<(u64, L)>,
    last: [Option<u64>; 3],
    /// Images dropped unpaired (pushed out by newer ones, or older than a
    /// frame already made).
    pub unpaired: u64,
}

impl<C, D, L> Pairer<C, D, L> {
    pub fn new(tolerance_ns: u64, want_labels: bool) -> Self {
        Self {
            tolerance_ns,
            want_labels,
            colour: VecDeque::new(),
            depth: VecDeque::new(),
            labels: VecDeque::new(),
            last: [None; 3],
            unpaired: 0,
        }
    }

    /// Refuses a stamp older than the last one seen on `stream`, before
    /// the image is decoded (decoding is the expensive part).
    pub fn check_order(&self, stream: Stream, stamp_ns: u64) -> Result<(), DecodeError> {
        match self.last.get(slot(stream)).copied().flatten() {
            Some(last_ns) if stamp_ns < last_ns => {
                Err(DecodeError::Backwards { stamp_ns, last_ns })
            }
            _ => Ok(()),
        }
    }

    pub fn push_colour(&mut self, stamp_ns: u64, c: C) -> Result<(), DecodeError> {
        self.check_order(Stream::Colour, stamp_ns)?;
        self.last[0] = Some(stamp_ns);
        push(&mut self.colour, stamp_ns, c, &mut self.unpaired);
        Ok(())
    }

    pub fn push_depth(&mut self, stamp_ns: u64, d: D) -> Result<(), DecodeError> {
        self.check_order(Stream::Depth, stamp_ns)?;
        self.last[1] = Some(stamp_ns);
        push(&mut self.depth, stamp_ns, d, &mut self.unpaired);
        Ok(())
    }

    pub fn push_labels(&mut self, stamp_ns: u64, l: L) -> Result<(), DecodeError> {
        self.check_order(Stream::Labels, stamp_ns)?;
        self.last[2] = Some(stamp_ns);
        push(&mut self.labels, stamp_ns, l, &mut self.unpaired);
        Ok(())
    }

    /// The newest complete frame, if any; it and everything older leave
    /// the queues (an older frame completed later would be out of date).
    pub fn take(&mut self) -> Option<Paired<C, D, L>> {
        let tol = self.tolerance_ns;
        let near = |a: u64, b: u64| a.abs_diff(b) <= tol;
        let (ci, di, li) = self
            .colour
            .iter()
            .enumerate()
            .rev()
            .find_map(|(ci, (cs, _))| {
                let di = closest(&self.depth, *cs).filter(|&i| near(self.depth[i].0, *cs))?;
                let li = if self.want_labels {
                    Some(closest(&self.labels, *cs).filter(|&i| near(self.labels[i].0, *cs))?)
                } else {
                    None
                };
                Some((ci, di, li))
            })?;
        let (stamp_ns, colour) = take_at(&mut self.colour, ci, &mut self.unpaired)?;
        let (_, depth) = take_at(&mut self.depth, di, &mut self.unpaired)?;
        let labels = match li {
            Some(li) => Some(take_at(&mut self.labels, li, &mut self.unpaired)?.1),
            None => None,
        };
        Some(Paired {
            stamp_ns,
            colour,
            depth,
            labels,
        })
    }
}

fn slot(stream: Stream) -> usize {
    match stream {
        Stream::Colour => 0,
        Stream::Depth => 1,
        Stream::Labels | Stream::CameraInfo => 2,
    }
}

fn push<T>(queue: &mut VecDeque<(u64, T)>, stamp_ns: u64, value: T, unpaired: &mut u64) {
    if queue.len() == KEEP {
        queue.pop_front();
        *unpaired += 1;
    }
    queue.push_back((stamp_ns, value));
}

/// Index of the entry whose stamp is nearest `stamp_ns`.
fn closest<T>(queue: &VecDeque<(u64, T)>, stamp_ns: u64) -> Option<usize> {
    queue
        .iter()
        .enumerate()
        .min_by_key(|(_, (s, _))| s.abs_diff(stamp_ns))
        .map(|(i, _)| i)
}

/// Removes entry `index` and every older one (counted as unpaired).
fn take_at<T>(
    queue: &mut VecDeque<(u64, T)>,
    index: usize,
    unpaired: &mut u64,
) -> Option<(u64, T)> {
    for _ in 0..index {
        queue.pop_front();
        *unpaired += 1;
    }
    queue.pop_front()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;

    const MS: u64 = 1_000_000;

    #[test]
    fn images_within_the_tolerance_pair_and_others_wait() {
        let mut p: Pairer<u32, u32, u32> = Pairer::new(5 * MS, false);
        p.push_colour(100 * MS, 1).unwrap();
        assert!(p.take().is_none());
        p.push_depth(120 * MS, 2).unwrap();
        assert!(p.take().is_none(), "20 ms apart is not one frame");
        p.push_colour(133 * MS, 3).unwrap();
        p.push_depth(134 * MS, 4).unwrap();
        let f = p.take().unwrap();
        assert_eq!(
            (f.stamp_ns, f.colour, f.depth, f.labels),
            (133 * MS, 3, 4, None)
        );
        // The older colour and depth went with it, unpaired.
        assert_eq!(p.unpaired, 2);
        assert!(p.take().is_none());
    }

    #[test]
    fn labels_are_waited_for_when_wanted() {
        let mut p: Pairer<u32, u32, u32> = Pairer::new(5 * MS, true);
        p.push_colour(100 * MS, 1).unwrap();
        p.push_depth(100 * MS, 2).unwrap();
        assert!(p.take().is_none());
        p.push_labels(101 * MS, 3).unwrap();
        assert_eq!(p.take().unwrap().labels, Some(3));
    }

    #[test]
    fn a_stamp_going_backwards_is_refused_and_changes_nothing() {
        let mut p: Pairer<u32, u32, u32> = Pairer::new(5 * MS, false);
        p.push_colour(200 * MS, 1).unwrap();
        let err = p.push_colour(100 * MS, 2).unwrap_err();
        assert_eq!(err.reason(), "stamp_backwards");
        p.push_depth(200 * MS, 3).unwrap();
        assert_eq!(p.take().unwrap().colour, 1);
    }

    #[test]
    fn queues_stay_bounded() {
        let mut p: Pairer<u32, u32, u32> = Pairer::new(0, false);
        for i in 0..100 {
            p.push_colour(i * MS, 0).unwrap();
        }
        assert_eq!(p.colour.len(), KEEP);
        assert_eq!(p.unpaired, 100 - KEEP as u64);
    }
}
