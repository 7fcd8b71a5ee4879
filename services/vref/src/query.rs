use std::time::{Duration, Instant};

use anyhow::Context;
use vref_config::Config;
use vref_wire::ReferenceAnswer;
use vref_wire::ipc::{IpcError, ReferenceClient};

use crate::cli::QueryArgs;
use crate::failure::{Blame, Failure};
use crate::stdout;

pub fn run(args: &QueryArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let timeout = Duration::from_millis(args.timeout_ms);
    let name = format!("vref-query-{}", std::process::id());
    let mut client = ReferenceClient::connect(&config.ipc, &name)
        .context("connecting to the matcher's reference service")
        .runtime()?;
    let start = Instant::now();
    let answer = match (&args.human_object, &args.ray) {
        (Some(id), _) => client.by_human_object(*id, timeout),
        (None, Some(r)) => {
            client.by_ray([r[0], r[1], r[2]], [r[3], r[4], r[5]], args.cone, timeout)
        }
        (None, None) => client.latest_gesture(timeout),
    }
    .map_err(|e| {
        // Only when nobody serves is the matcher missing; a timeout with a
        // server means it is running but did not answer in time.
        let hint = match e {
            IpcError::NoServer { .. } => format!(
                "asking the matcher (is vref-matcher running with the same [ipc] settings: namespace `{}`, prefix `{}`?)",
                config.ipc.namespace, config.ipc.prefix
            ),
            _ => "asking the matcher".to_owned(),
        };
        anyhow::Error::from(e).context(hint)
    })
    .runtime()?;
    let rtt = start.elapsed();
    let text = if args.json {
        json(&answer, rtt)
    } else {
        describe(&answer, rtt)
    };
    stdout::print(&format!("{text}\n"))
}

/// One line a person can read.
pub fn describe(a: &ReferenceAnswer, rtt: Duration) -> String {
    let status = a.status().name();
    let mut text = format!(
        "{status}: human object {} -> robot object {} at ({:.3}, {:.3}, {:.3}) m, confidence {:.2}",
        a.human_object_id,
        a.robot_track_id,
        a.position[0],
        a.position[1],
        a.position[2],
        a.confidence
    );
    if !a.alternatives().is_empty() {
        let alts: Vec<String> = a
            .alternatives()
            .iter()
            .map(|alt| format!("{} ({:.2})", alt.robot_track_id, alt.confidence))
            .collect();
        text += &format!("; alternatives {}", alts.join(", "));
    }
    text += &format!(
        "; snapshots robot #{} ({:.0} ms old), human #{} ({:.0} ms old), solved {:.0} ms ago",
        a.robot_sequence,
        a.robot_age_us as f64 / 1000.0,
        a.human_sequence,
        a.human_age_us as f64 / 1000.0,
        a.solve_age_us as f64 / 1000.0,
    );
    if a.ray_age_us > 0 {
        text += &format!("; ray {:.0} ms old", a.ray_age_us as f64 / 1000.0);
    }
    text += &format!("; round trip {} us", rtt.as_micros());
    text
}

#[derive(serde::Serialize)]
struct JsonAnswer {
    status: &'static str,
    request_id: u64,
    human_object_id: u64,
    robot_track_id: u64,
    position: [f32; 3],
    confidence: f32,
    alternatives: Vec<JsonAlternative>,
    robot_sequence: u64,
    human_sequence: u64,
    robot_age_us: u64,
    human_age_us: u64,
    solve_age_us: u64,
    ray_age_us: u64,
    /// The answered object in the human view's frame, when known.
    human_frame_position: Option<[f32; 3]>,
    /// Whether that position came through the estimated motion.
    human_position_from_motion: bool,
    solved: bool,
    rtt_us: u128,
}

#[derive(serde::Serialize)]
struct JsonAlternative {
    robot_track_id: u64,
    confidence: f32,
}

pub fn json(a: &ReferenceAnswer, rtt: Duration) -> String {
    let line = JsonAnswer {
        status: a.status().name(),
        request_id: a.request_id,
        human_object_id: a.human_object_id,
        robot_track_id: a.robot_track_id,
        position: a.position,
        confidence: a.confidence,
        alternatives: a
            .alternatives()
            .iter()
            .map(|alt| JsonAlternative {
                robot_track_id: alt.robot_track_id,
                confidence: alt.confidence,
            })
            .collect(),
        robot_sequence: a.robot_sequence,
        human_sequence: a.human_sequence,
        robot_age_us: a.robot_age_us,
        human_age_us: a.human_age_us,
        solve_age_us: a.solve_age_us,
        ray_age_us: a.ray_age_us,
        human_frame_position: (a.flags & ReferenceAnswer::FLAG_HUMAN_POSITION != 0)
            .then_some(a.human_frame_position),
        human_position_from_motion: a.flags & ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION != 0,
        solved: a.solved(),
        rtt_us: rtt.as_micros(),
    };
    serde_json::to_string(&line).unwrap_or_default()
}
