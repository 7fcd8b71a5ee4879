//! Answers for ROS 2: the Trigger service's reply (the answer as one line
//! of JSON, the same fields `vref view` publishes) and the
//! `PointStamped` of an `ok` answer. Pure.

use vref_view::Asked;
use vref_wire::{AnswerStatus, ReferenceAnswer};

use crate::msg::{Header, Point, PointStamped, Time, TriggerResponse};

/// The service's reply to a latest-gesture answer: `success` only for
/// `ok`, the message is the answer as one line of JSON.
pub fn trigger_response(asked: &Asked) -> TriggerResponse {
    TriggerResponse {
        success: asked.answer.status() == AnswerStatus::Ok,
        message: vref_view::json::answer(asked).to_string(),
    }
}

/// The reply when the matcher could not be asked: `status` "error" and
/// the reason, still one line of JSON.
pub fn trigger_failure(reason: &str) -> TriggerResponse {
    TriggerResponse {
        success: false,
        message: serde_json::json!({"status": "error", "error": reason}).to_string(),
    }
}

/// The referenced object of an `ok` answer, in the robot camera frame.
pub fn referenced_point(
    answer: &ReferenceAnswer,
    robot_frame: &str,
    stamp: Time,
) -> Option<PointStamped> {
    let p = answer.position.map(f64::from);
    (answer.status() == AnswerStatus::Ok && p.iter().all(|v| v.is_finite())).then(|| PointStamped {
        header: Header {
            stamp,
            frame_id: robot_frame.to_owned(),
        },
        point: Point::from(p),
    })
}

/// Which ok answers are news: a different human or robot object than the
/// last one published (the same gesture asked again gives the same pair).
#[derive(Debug, Default)]
pub struct NewAnswers {
    last: Option<(u64, u64)>,
}

impl NewAnswers {
    pub fn is_new(&mut self, answer: &ReferenceAnswer) -> bool {
        if answer.status() != AnswerStatus::Ok {
            return false;
        }
        let key = (answer.human_object_id, answer.robot_track_id);
        let new = self.last != Some(key);
        self.last = Some(key);
        new
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;

    fn answer(status: AnswerStatus, human: u64, robot: u64) -> ReferenceAnswer {
        ReferenceAnswer {
            human_object_id: human,
            robot_track_id: robot,
            position: [0.1, 0.2, 0.9],
            ..ReferenceAnswer::empty(1, status)
        }
    }

    #[test]
    fn the_reply_is_one_json_line_and_success_only_for_ok() {
        for (status, success) in [
            (AnswerStatus::Ok, true),
            (AnswerStatus::Ambiguous, false),
            (AnswerStatus::Stale, false),
        ] {
            let asked = Asked {
                answer: answer(status, 1, 2),
                round_trip_us: 40,
                received_ns: 0,
            };
            let r = trigger_response(&asked);
            assert_eq!(r.success, success);
            assert!(!r.message.contains('\n'));
            let v: serde_json::Value = serde_json::from_str(&r.message).unwrap();
            assert_eq!(v["status"], status.name());
            assert_eq!(v["robot_track_id"], 2);
        }
        let f = trigger_failure("no matcher");
        assert!(!f.success);
        let v: serde_json::Value = serde_json::from_str(&f.message).unwrap();
        assert_eq!(v["status"], "error");
    }

    #[test]
    fn only_ok_answers_give_a_point_and_only_new_ones_are_news() {
        let ok = answer(AnswerStatus::Ok, 1, 2);
        let p = referenced_point(&ok, "cam", Time::default()).unwrap();
        assert_eq!(p.header.frame_id, "cam");
        assert!((p.point.z - 0.9).abs() < 1e-6);
        assert!(
            referenced_point(&answer(AnswerStatus::NoMatch, 1, 2), "cam", Time::default())
                .is_none()
        );
        let mut news = NewAnswers::default();
        assert!(news.is_new(&ok));
        assert!(!news.is_new(&ok));
        assert!(!news.is_new(&answer(AnswerStatus::Ambiguous, 3, 4)));
        assert!(news.is_new(&answer(AnswerStatus::Ok, 3, 4)));
    }
}
