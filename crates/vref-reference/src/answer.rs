use std::time::{Duration, Instant};

use vref_wire::{
    Alternative, AnswerStatus, MAX_ALTERNATIVES, PointingRay, QueryKind, Ray, ReferenceAnswer,
    ReferenceQuery, SCHEMA_VERSION,
};

use crate::ReferenceState;
use crate::resolve_ray;
use crate::state::Feed;

impl ReferenceState {
    /// Answers a reference query from the cached solution, solving first
    /// if the snapshots changed since.
    pub fn answer(&mut self, query: &ReferenceQuery, now: Instant) -> ReferenceAnswer {
        let mut answer = ReferenceAnswer::empty(query.request_id, AnswerStatus::BadRequest);
        if query.schema_version != SCHEMA_VERSION {
            return answer;
        }
        let kind = match query.kind {
            k if k == QueryKind::HumanObject as u32 => QueryKind::HumanObject,
            k if k == QueryKind::Ray as u32 => QueryKind::Ray,
            k if k == QueryKind::LatestGesture as u32 => QueryKind::LatestGesture,
            _ => return answer,
        };
        let (Some(robot), Some(human)) = (&self.robot, &self.human) else {
            answer.status = AnswerStatus::NotReady as u32;
            return answer;
        };
        let ages = (age(robot, now), age(human, now));
        answer.robot_sequence = robot.snapshot.sequence;
        answer.human_sequence = human.snapshot.sequence;
        answer.robot_age_us = micros(ages.0);
        answer.human_age_us = micros(ages.1);

        let Some(human_index) = self.human_target(kind, query, &mut answer) else {
            return self.mark_stale(answer, ages);
        };
        answer.human_object_id = self
            .human
            .as_ref()
            .map_or(0, |h| h.snapshot.graph.objects()[human_index].id);
        match self.refresh() {
            Ok(true) => answer.flags |= ReferenceAnswer::FLAG_SOLVED,
            Ok(false) => {}
            Err(_) => {
                answer.status = AnswerStatus::NotReady as u32;
                return answer;
            }
        }
        self.fill_match(human_index, &mut answer);
        self.mark_stale(answer, ages)
    }

    /// The human-view object the query is about; `None` with the answer's
    /// status set when there is none.
    fn human_target(
        &self,
        kind: QueryKind,
        query: &ReferenceQuery,
        answer: &mut ReferenceAnswer,
    ) -> Option<usize> {
        let graph = &self.human.as_ref()?.snapshot.graph;
        let by_ray = |ray: &Ray, answer: &mut ReferenceAnswer| {
            let found = resolve_ray(graph, ray);
            if found.is_none() {
                answer.status = AnswerStatus::NoMatch as u32;
            }
            found
        };
        match kind {
            QueryKind::HumanObject => {
                let found = graph.index_of(query.human_object_id);
                if found.is_none() {
                    answer.status = AnswerStatus::BadRequest as u32;
                }
                found
            }
            QueryKind::Ray => match query_ray(query).validate() {
                Ok(ray) => by_ray(&ray, answer),
                Err(_) => {
                    answer.status = AnswerStatus::BadRequest as u32;
                    None
                }
            },
            QueryKind::LatestGesture => match &self.gesture {
                Some(ray) => by_ray(ray, answer),
                None => {
                    answer.status = AnswerStatus::NotReady as u32;
                    None
                }
            },
        }
    }

    /// Writes the robot object matched to human object `row` (if any),
    /// the solution's confidence in that answer and the next-best
    /// alternatives.
    fn fill_match(&self, row: usize, answer: &mut ReferenceAnswer) {
        let solution = self.cached.and(self.engine.solution());
        let (Some(solution), Some(robot)) = (solution, &self.robot) else {
            answer.status = AnswerStatus::NotReady as u32;
            return;
        };
        let objects = robot.snapshot.graph.objects();
        let m = objects.len();
        let soft = &solution.soft[row * m..(row + 1) * m];
        let total: f64 = soft.iter().map(|v| v.max(0.0)).sum();
        let share = |v: f64| {
            if total > 0.0 {
                v.max(0.0) / total
            } else {
                1.0 / m as f64
            }
        };
        let confidence = solution.confidence.get(row).copied().unwrap_or(0.0);
        let assigned = solution.assignment.get(row).copied().flatten();
        answer.confidence = confidence as f32;
        if let Some(col) = assigned {
            let matched = &objects[col];
            answer.robot_track_id = matched.id;
            answer.position = matched.position.coords.map(|c| c as f32).into();
        }
        // Alternatives: the best other columns (all columns when the
        // answer is "no partner"), with their soft shares.
        let best = next_best(soft, assigned.unwrap_or(usize::MAX));
        let mut count = 0;
        for (slot, b) in answer
            .alternatives
            .iter_mut()
            .zip(best.into_iter().flatten())
        {
            *slot = Alternative {
                robot_track_id: objects[b].id,
                confidence: share(soft[b]) as f32,
                reserved: 0,
            };
            count += 1;
        }
        answer.alternative_count = count;
        // Below the threshold the robot should ask "which one?", whether
        // the unsure answer is a partner or "no partner".
        answer.status = if confidence < self.ambiguity_threshold {
            AnswerStatus::Ambiguous as u32
        } else if assigned.is_none() {
            AnswerStatus::NoMatch as u32
        } else {
            AnswerStatus::Ok as u32
        };
    }

    /// Answers from a feed that went silent are `stale`, whatever else
    /// they say: the robot must not act on them as current.
    fn mark_stale(
        &self,
        mut answer: ReferenceAnswer,
        (robot, human): (Duration, Duration),
    ) -> ReferenceAnswer {
        let bad_request = answer.status == AnswerStatus::BadRequest as u32;
        if !bad_request && (robot > self.stale_after || human > self.stale_after) {
            answer.status = AnswerStatus::Stale as u32;
        }
        answer
    }
}

/// The columns with the highest soft values other than `chosen`, best
/// first (ties in column order), found in one pass without allocating:
/// this runs on the query path.
fn next_best(soft: &[f64], chosen: usize) -> [Option<usize>; MAX_ALTERNATIVES] {
    let mut best = [None; MAX_ALTERNATIVES];
    for b in (0..soft.len()).filter(|&b| b != chosen) {
        // Insertion into a short sorted list; the last entry falls off.
        let mut candidate = b;
        for slot in &mut best {
            match *slot {
                None => {
                    *slot = Some(candidate);
                    break;
                }
                Some(held) if soft[candidate] > soft[held] => {
                    *slot = Some(candidate);
                    candidate = held;
                }
                Some(_) => {}
            }
        }
    }
    best
}

fn age(feed: &Feed, now: Instant) -> Duration {
    now.saturating_duration_since(feed.received_at)
}

fn micros(d: Duration) -> u64 {
    u64::try_from(d.as_micros()).unwrap_or(u64::MAX)
}

fn query_ray(query: &ReferenceQuery) -> PointingRay {
    PointingRay {
        session: 0,
        sequence: 0,
        timestamp_ns: 0,
        origin: query.ray_origin,
        direction: query.ray_direction,
        cone_half_angle: query.cone_half_angle,
        confidence: 1.0,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::next_best;

    #[test]
    fn next_best_orders_the_others_and_skips_the_chosen() {
        let soft = [0.1, 0.5, 0.3, 0.9, 0.3, 0.05];
        assert_eq!(next_best(&soft, 3), [Some(1), Some(2), Some(4)]);
        assert_eq!(next_best(&soft, 1), [Some(3), Some(2), Some(4)]);
        assert_eq!(next_best(&[0.2, 0.7], 1), [Some(0), None, None]);
        assert_eq!(next_best(&[0.7], 0), [None, None, None]);
    }
}
