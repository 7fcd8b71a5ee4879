use std::time::{Duration, Instant};

use anyhow::Context;
use vref_bridge::RemoteClient;
use vref_bridge::json::AnswerJson;
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_wire::ipc::{IpcError, ReferenceClient};
use vref_wire::{AnswerStatus, ReferenceAnswer, ReferenceQuery};

use crate::cli::QueryArgs;
use crate::stdout;

pub fn run(args: &QueryArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let timeout = args.timeout();
    let query = query_of(args);
    let (answer, rtt) = match &args.remote {
        Some(endpoint) => ask_remote(args, &config, endpoint, query, timeout)?,
        None => ask_local(&config, query, timeout)?,
    };
    let text = if args.json {
        json(&answer, rtt)
    } else {
        describe(&answer, rtt)
    };
    stdout::print(&format!("{text}\n"))?;
    match exit_code(answer.status()) {
        0 => Ok(()),
        code => Err(Failure::Outcome(
            code,
            anyhow::anyhow!("the matcher answered {}", answer.status().name()),
        )),
    }
}

/// `vref query`'s exit code for an answer of `status` (as `vref query
/// --help` states): 0 for an answer from the solution (ok, ambiguous,
/// no_match); 3 bad_request, 4 not_ready, 5 stale. 1 (no matcher, no
/// answer in time) and 2 (bad input) come from failures before any answer.
pub fn exit_code(status: AnswerStatus) -> u8 {
    match status {
        AnswerStatus::Ok | AnswerStatus::Ambiguous | AnswerStatus::NoMatch => 0,
        AnswerStatus::BadRequest => 3,
        AnswerStatus::NotReady => 4,
        AnswerStatus::Stale => 5,
    }
}

/// The question the arguments ask (the request id is the client's).
pub fn query_of(args: &QueryArgs) -> ReferenceQuery {
    match (&args.human_object, &args.ray) {
        (Some(id), _) => ReferenceQuery::human_object(*id),
        (None, Some(r)) => ReferenceQuery::ray([r[0], r[1], r[2]], [r[3], r[4], r[5]], args.cone),
        (None, None) => ReferenceQuery::latest_gesture(),
    }
}

fn ask_local(
    config: &Config,
    query: ReferenceQuery,
    timeout: Duration,
) -> Result<(ReferenceAnswer, Duration), Failure> {
    let name = format!("vref-query-{}", std::process::id());
    let mut client = ReferenceClient::connect(&config.ipc, &name)
        .context("connecting to the matcher")
        .runtime()?;
    let start = Instant::now();
    let answer = client
        .ask(query, timeout)
        .map_err(|e| {
            // Only when nobody serves is the matcher missing; a timeout with
            // a server means it is running but did not answer in time.
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
    Ok((answer, start.elapsed()))
}

/// Over Zenoh, through the robot's bridge: `--prefix`, else the
/// configuration's `[bridge] prefix`, names the robot.
fn ask_remote(
    args: &QueryArgs,
    config: &Config,
    endpoint: &str,
    query: ReferenceQuery,
    timeout: Duration,
) -> Result<(ReferenceAnswer, Duration), Failure> {
    let prefix = args.prefix.as_deref().unwrap_or(&config.bridge.prefix);
    vref_config::check_endpoint(endpoint)
        .map_err(|e| anyhow::anyhow!("--remote `{endpoint}`: {e}"))
        .bad_input()?;
    vref_config::check_prefix(prefix)
        .map_err(|e| anyhow::anyhow!("--prefix `{prefix}`: {e}"))
        .bad_input()?;
    // RemoteClient's error names the endpoint already.
    let mut client = RemoteClient::connect(endpoint, prefix, args.encoding)
        .map_err(anyhow::Error::from)
        .runtime()?;
    let start = Instant::now();
    let answer = client
        .ask(query, timeout)
        .context("asking through the bridge")
        .runtime()?;
    Ok((answer, start.elapsed()))
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

/// The answer's JSON fields (those a remote controller gets from the
/// bridge, vref_bridge::json::AnswerJson) and this client's round trip.
#[derive(serde::Serialize)]
struct JsonLine {
    #[serde(flatten)]
    answer: AnswerJson,
    rtt_us: u128,
}

pub fn json(a: &ReferenceAnswer, rtt: Duration) -> String {
    let line = JsonLine {
        answer: AnswerJson::from(a),
        rtt_us: rtt.as_micros(),
    };
    serde_json::to_string(&line).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_codes_are_distinct_for_answers_that_are_not_a_reference() {
        let codes: Vec<u8> = AnswerStatus::ALL.iter().map(|s| exit_code(*s)).collect();
        assert_eq!(exit_code(AnswerStatus::Ok), 0);
        assert_eq!(exit_code(AnswerStatus::Ambiguous), 0);
        assert_eq!(exit_code(AnswerStatus::NoMatch), 0);
        assert_eq!(exit_code(AnswerStatus::BadRequest), 3);
        assert_eq!(exit_code(AnswerStatus::NotReady), 4);
        assert_eq!(exit_code(AnswerStatus::Stale), 5);
        assert_eq!(codes.len(), 6);
    }
}
