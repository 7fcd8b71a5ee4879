use nalgebra::Point3;
use vref_match::{OkRule, Solution, Verdict};
use vref_scene::Side;
use vref_wire::{
    Alternative, AnswerStatus, MAX_ALTERNATIVES, PointingRay, QueryKind, Ray, ReferenceAnswer,
    ReferenceQuery, SCHEMA_VERSION,
};

use crate::ReferenceState;
use crate::solver::Solved;
use crate::stamp::{Now, capture_age, micros};
use crate::{Pointed, resolve_ray};

/// The status of row `row`'s answer at `confidence` as `rule` decides it
/// (the same decision `vref eval --answers` records), before any
/// staleness.
pub fn outcome(solution: &Solution, row: usize, confidence: f64, rule: &OkRule) -> AnswerStatus {
    match solution.verdict(row, confidence, rule) {
        Verdict::Ok => AnswerStatus::Ok,
        Verdict::Ambiguous => AnswerStatus::Ambiguous,
        Verdict::NoMatch => AnswerStatus::NoMatch,
    }
}

impl ReferenceState {
    /// Answers a reference query from the latest finished solution and the
    /// snapshots it was solved for; never solves and makes no heap
    /// allocation.
    pub fn answer(&self, query: &ReferenceQuery, now: &Now) -> ReferenceAnswer {
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
        let Some(solved) = self.solved.as_deref() else {
            answer.status = AnswerStatus::NotReady as u32;
            self.name_refusal(&mut answer, [true; 2]);
            return answer;
        };
        answer.robot_sequence = solved.robot.sequence;
        answer.human_sequence = solved.human.sequence;
        answer.robot_age_us = micros(capture_age(solved.robot.timestamp_ns, now));
        answer.human_age_us = micros(capture_age(solved.human.timestamp_ns, now));
        answer.solve_age_us = micros(
            now.instant
                .saturating_duration_since(solved.finished.instant),
        );
        if solved.real {
            answer.flags |= ReferenceAnswer::FLAG_SOLVED;
        }
        let Some(target) = self.human_target(solved, kind, query, now, &mut answer) else {
            return self.mark_stale(answer);
        };
        answer.human_object_id = solved.human.graph.objects()[target.row].id;
        self.fill_match(solved, target, &mut answer);
        self.mark_stale(answer)
    }

    /// The row of the solved human view the query is about, with the
    /// share of the pointing in it (1 for a query by id); `None` with the
    /// answer's status set when there is none.
    fn human_target(
        &self,
        solved: &Solved,
        kind: QueryKind,
        query: &ReferenceQuery,
        now: &Now,
        answer: &mut ReferenceAnswer,
    ) -> Option<Pointed> {
        let graph = &solved.human.graph;
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
                found.map(|row| Pointed { row, share: 1.0 })
            }
            QueryKind::Ray => match query_ray(query).validate() {
                Ok(ray) => by_ray(&ray, answer),
                Err(_) => {
                    answer.status = AnswerStatus::BadRequest as u32;
                    None
                }
            },
            QueryKind::LatestGesture => match &self.gesture {
                Some(ray) => {
                    // At least 1 us, so that 0 keeps meaning "no stored ray".
                    answer.ray_age_us = micros(capture_age(ray.timestamp_ns, now)).max(1);
                    by_ray(ray, answer)
                }
                None => {
                    answer.status = AnswerStatus::NotReady as u32;
                    None
                }
            },
        }
    }

    /// Writes the robot object matched to the target's human object (if
    /// any), the confidence in that answer (the solution's, times the
    /// target's pointing share: the answer is right only if the person
    /// meant that object), the next-best alternatives and the answered
    /// object in the human view's frame.
    fn fill_match(&self, solved: &Solved, target: Pointed, answer: &mut ReferenceAnswer) {
        let row = target.row;
        let solution = &solved.solution;
        let objects = solved.robot.graph.objects();
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
        let confidence = solution.confidence.get(row).copied().unwrap_or(0.0) * target.share;
        let assigned = solution.assignment.get(row).copied().flatten();
        answer.confidence = confidence as f32;
        let human_object = &solved.human.graph.objects()[row];
        answer.human_frame_position = to_f32(&human_object.position);
        answer.flags |= ReferenceAnswer::FLAG_HUMAN_POSITION;
        if let Some(col) = assigned {
            let matched = &objects[col];
            answer.robot_track_id = matched.id;
            answer.position = to_f32(&matched.position);
            // Where the robot's object is in the headset's frame: through
            // the motion the answer rests on, when the method gives one.
            if let Some(motion) = &solution.motion {
                let back =
                    motion.rotation.transpose() * (matched.position.coords - motion.translation);
                answer.human_frame_position = to_f32(&Point3::from(back));
                answer.flags |= ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION;
            }
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
        answer.status = outcome(solution, row, confidence, &self.ok_rule) as u32;
    }

    /// Answers resting on a snapshot or a ray captured too long ago are
    /// `stale`, whatever else they say: the robot must not act on them as
    /// current.
    fn mark_stale(&self, mut answer: ReferenceAnswer) -> ReferenceAnswer {
        let status = answer.status();
        if matches!(status, AnswerStatus::BadRequest | AnswerStatus::NotReady) {
            return answer;
        }
        let limit = micros(self.stale_after);
        let ray_old = answer.ray_age_us > micros(self.ray_max_age);
        let old = [answer.robot_age_us > limit, answer.human_age_us > limit];
        if old[0] || old[1] || ray_old {
            answer.status = AnswerStatus::Stale as u32;
            self.name_refusal(&mut answer, old);
        }
        answer
    }

    /// Names the refusal behind an answer that has nothing fresher: the
    /// latest refused snapshot of a side (`sides`: robot, human) whose
    /// snapshot is old or missing, robot first.
    fn name_refusal(&self, answer: &mut ReferenceAnswer, sides: [bool; 2]) {
        let refused = [Side::Robot, Side::Human]
            .into_iter()
            .filter(|&side| sides[side as usize])
            .find_map(|side| self.last_refused(side));
        if let Some(reason) = refused {
            answer.refusal = reason as u32;
            answer.flags |= ReferenceAnswer::FLAG_REFUSAL;
        }
    }
}

fn to_f32(p: &Point3<f64>) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
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
