//! `vref bench ros2`: capture stamp to MarkerArray arrival through a real
//! ROS 2 peer, beside the bare DDS floor of the same run.
//!
//! The command re-runs itself in a network namespace with loopback only
//! (vref_harness::netns), where it starts a matcher and vref-ros2 under an
//! isolated configuration, and an rclpy peer (bench_ros2_peer.py, written
//! out beside the logs) that publishes one RGB-D frame at --rate with a
//! fresh stamp each time and times, per frame, vref-ros2's markers and a
//! trivial rclpy relay's echo of the same frame. Percentiles are nearest
//! rank (vref_measure). vref-ros2's resident memory is read from /proc
//! when the peer is warm and when it stops publishing.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::Stdio;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use anyhow::{Context, anyhow, bail};
use vref_config::Config;
use vref_harness::launch::{Services, binary, keep_logs_if, prepare};
use vref_harness::netns;
use vref_logging::exit::{Blame, Failure};
use vref_perception::folder::RgbdImages;

use crate::cli::BenchRos2Args;
use crate::stdout;

const PEER: &str = include_str!("bench_ros2_peer.py");
/// The rclpy nodes' Fast DDS: UDP only (vref-ros2's RustDDS has no
/// shared-memory transport, and the floor must take the path its images
/// take), with socket buffers of 4 MiB as RustDDS asks for (8 MiB,
/// capped by the kernel's rmem_max; Fast DDS otherwise keeps the 208 KiB
/// default, and a 900 kB image sent best effort overflows it).
const FASTDDS_PROFILE: &str = r#"<?xml version="1.0" encoding="UTF-8" ?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <transport_descriptors>
    <transport_descriptor>
      <transport_id>vref_bench_udp</transport_id>
      <type>UDPv4</type>
      <sendBufferSize>4194304</sendBufferSize>
      <receiveBufferSize>4194304</receiveBufferSize>
    </transport_descriptor>
  </transport_descriptors>
  <participant profile_name="vref_bench" is_default_profile="true">
    <rtps>
      <userTransports>
        <transport_id>vref_bench_udp</transport_id>
      </userTransports>
      <useBuiltinTransports>false</useBuiltinTransports>
    </rtps>
  </participant>
</profiles>
"#;
/// Hang guard beyond --seconds: discovery and warm-up (the peer gives up
/// after 60 s), start and stop of the services.
const GUARD: Duration = Duration::from_secs(180);

/// The command's JSON line; field order is the documented contract's.
#[derive(Debug, serde::Serialize)]
struct Report {
    frames: usize,
    p50_ms: f64,
    p99_ms: f64,
    dropped: usize,
    floor_p50_ms: f64,
    floor_p99_ms: f64,
    p90_ms: f64,
    max_ms: f64,
    floor_p90_ms: f64,
    floor_max_ms: f64,
    floor_dropped: usize,
    rate_hz: f64,
    seconds: f64,
    width: u32,
    height: u32,
    /// Frames the publisher sent late (it could not keep the rate).
    publisher_late: u64,
    rss_start_kb: Option<u64>,
    rss_end_kb: Option<u64>,
    /// Every 10 s from warm to the end.
    rss_every_10s_kb: Vec<u64>,
}

pub fn ros2(args: &BenchRos2Args) -> Result<(), Failure> {
    if !args.inside_namespace {
        return reenter(args);
    }
    netns::check_loopback_only()
        .context("vref bench ros2 runs DDS only in a loopback-only network namespace")
        .runtime()?;
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let python = match &args.python {
        Some(p) => p.clone(),
        None => std::env::var_os("VREF_ROS2_PYTHON")
            .map(Into::into)
            .ok_or_else(|| {
                anyhow!("no python with rclpy: give --python or set VREF_ROS2_PYTHON (tools/test.sh installs one in target/ros2-venv)")
            })
            .bad_input()?,
    };
    let images = RgbdImages::load(&args.frame, config.perception.image_limit())
        .with_context(|| format!("--frame {}", args.frame.display()))
        .bad_input()?;
    let bin_dir = crate::harness::bin_dir()?;
    let isolation = prepare(&config, &bin_dir, "bench-ros2", "vbr")
        .map_err(|e| anyhow!(e))
        .runtime()?;
    let ros2_bin = binary(&bin_dir, "vref-ros2")
        .map_err(|e| anyhow!(e))
        .runtime()?;
    let dir = isolation.dir.path().to_owned();
    write_frame(&images, &dir.join("frame"))?;
    let peer = dir.join("bench_ros2_peer.py");
    std::fs::write(&peer, PEER)
        .with_context(|| format!("writing {}", peer.display()))
        .runtime()?;

    let mut services = Services::new(&dir);
    let config_path = isolation.config_path.clone();
    let started = (|| -> anyhow::Result<()> {
        services.start_some(&isolation.binaries, &config_path, &[], |name| {
            name == "vref-matcher"
        })?;
        services.start(
            "vref-ros2",
            &ros2_bin,
            &["--config".as_ref(), config_path.as_os_str()],
        )?;
        Ok(())
    })();
    let outcome =
        started.and_then(|()| run_peer(args, &python, &peer, &dir.join("frame"), &services));
    let stopped = services.stop();
    keep_logs_if(outcome.is_err() || stopped.is_err(), isolation.dir);
    let (mut report, peer_json) = outcome.runtime()?;
    report.width = images.colour.width();
    report.height = images.colour.height();
    tracing::debug!(%peer_json, "peer");
    if args.json {
        stdout::print(&format!(
            "{}\n",
            serde_json::to_string(&report)
                .context("encoding")
                .runtime()?
        ))?;
    } else {
        stdout::print(&table(&report))?;
    }
    stopped.map_err(|e| anyhow!(e)).runtime()
}

/// Runs this command again inside a new loopback-only network namespace,
/// its output passed through.
fn reenter(args: &BenchRos2Args) -> Result<(), Failure> {
    let exe = crate::harness::vref_exe()?;
    let mut command = netns::in_loopback_namespace(&exe);
    command
        .args(std::env::args_os().skip(1))
        .arg("--inside-namespace")
        .stdin(Stdio::null());
    let mut child = command
        .spawn()
        .context("starting `unshare` (util-linux) for a loopback-only network namespace")
        .runtime()?;
    let limit = GUARD + Duration::from_secs_f64(args.seconds);
    let started = Instant::now();
    loop {
        if let Some(status) = child.try_wait().context("waiting").runtime()? {
            return match status.code() {
                Some(0) => Ok(()),
                Some(2) => Err(anyhow!("vref bench ros2 refused its input (above)")).bad_input(),
                _ => Err(anyhow!(
                    "the benchmark in its network namespace failed ({status}); where the namespace \
                     cannot be made (not root, no util-linux unshare or iproute2 ip) it fails here"
                ))
                .runtime(),
            };
        }
        if started.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            return Err(anyhow!("the benchmark did not finish within {limit:?}")).runtime();
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The frame as the raw buffers the peer publishes.
fn write_frame(images: &RgbdImages, dir: &Path) -> Result<(), Failure> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating {}", dir.display()))
        .runtime()?;
    let k = images.camera.intrinsics;
    // The peer publishes millimetres (16UC1).
    let scale = images.depth.metres_per_unit() / 0.001;
    let depth: Vec<u8> = images
        .depth
        .pixels()
        .as_raw()
        .iter()
        .flat_map(|&d| {
            let mm = (f64::from(d) * scale)
                .round()
                .clamp(0.0, f64::from(u16::MAX)) as u16;
            mm.to_le_bytes()
        })
        .collect();
    let frame = serde_json::json!({
        "width": images.colour.width(), "height": images.colour.height(),
        "fx": k.fx(), "fy": k.fy(), "cx": k.cx(), "cy": k.cy(),
    });
    for (name, bytes) in [
        ("rgb.raw", images.colour.as_raw().clone()),
        ("depth.raw", depth),
        ("frame.json", frame.to_string().into_bytes()),
    ] {
        std::fs::write(dir.join(name), bytes)
            .with_context(|| format!("writing {name}"))
            .runtime()?;
    }
    Ok(())
}

/// Resident memory of `pid` in kB (VmRSS), if readable.
fn rss_kb(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
}

#[derive(Debug, serde::Deserialize)]
struct PeerResult {
    published: Vec<u64>,
    markers: Vec<Option<i64>>,
    relayed: Vec<Option<i64>>,
    publisher_late: u64,
}

fn run_peer(
    args: &BenchRos2Args,
    python: &Path,
    peer: &Path,
    frame: &Path,
    services: &Services,
) -> anyhow::Result<(Report, String)> {
    let log = std::fs::File::create(frame.with_file_name("peer.log"))?;
    let profile = frame.with_file_name("fastdds.xml");
    std::fs::write(&profile, FASTDDS_PROFILE)?;
    let mut child = std::process::Command::new(python)
        .arg(peer)
        .arg("--frame")
        .arg(frame)
        .arg("--seconds")
        .arg(args.seconds.to_string())
        .arg("--rate")
        .arg(args.rate.to_string())
        .env("FASTDDS_DEFAULT_PROFILES_FILE", &profile)
        .env("FASTRTPS_DEFAULT_PROFILES_FILE", &profile)
        .env("RMW_FASTRTPS_USE_QOS_FROM_XML", "0")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(log)
        .spawn()
        .with_context(|| format!("starting {}", python.display()))?;
    let stdout = child.stdout.take().context("the peer's output")?;
    let (lines, received) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            let Ok(line) = line else { break };
            if lines.send(line).is_err() {
                break;
            }
        }
    });
    let ros2_pid = services
        .pid("vref-ros2")
        .context("vref-ros2 is not running")?;
    let deadline = Instant::now() + GUARD + Duration::from_secs_f64(args.seconds);
    let mut rss_start = None;
    let mut rss_samples = Vec::new();
    let mut next_sample: Option<Instant> = None;
    let mut result = None;
    while result.is_none() {
        if let Some(at) = next_sample
            && Instant::now() >= at
        {
            rss_samples.extend(rss_kb(ros2_pid));
            next_sample = Some(at + Duration::from_secs(10));
        }
        let wait = deadline.saturating_duration_since(Instant::now());
        match received.recv_timeout(wait.min(Duration::from_millis(200))) {
            Ok(line) if line == "warm" => {
                rss_start = rss_kb(ros2_pid);
                next_sample = Some(Instant::now() + Duration::from_secs(10));
            }
            Ok(line) => result = Some(line),
            Err(mpsc::RecvTimeoutError::Timeout) if Instant::now() < deadline => {}
            Err(mpsc::RecvTimeoutError::Timeout) => {
                child.kill().ok();
                child.wait().ok();
                bail!("the rclpy peer did not finish within its time (hang guard)");
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        }
    }
    let rss_end = rss_kb(ros2_pid);
    // The peer exits once it has printed; bounded all the same.
    let exited = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait()? {
            break s;
        }
        if exited.elapsed() > Duration::from_secs(20) {
            child.kill().ok();
            break child.wait()?;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let line = result.ok_or_else(|| {
        anyhow!(
            "the rclpy peer ended ({status}) without results; see {}",
            frame.with_file_name("peer.log").display()
        )
    })?;
    if !status.success() {
        bail!("the rclpy peer failed ({status}): {line}");
    }
    let r: PeerResult = serde_json::from_str(&line).context("the peer's results")?;
    let ms =
        |v: &[Option<i64>]| -> Vec<f64> { v.iter().flatten().map(|&ns| ns as f64 / 1e6).collect() };
    let (lat, floor) = (ms(&r.markers), ms(&r.relayed));
    let p = |v: &[f64], q: f64| vref_measure::percentile_of(v, q).unwrap_or(f64::NAN);
    let report = Report {
        frames: r.published.len(),
        p50_ms: p(&lat, 0.5),
        p99_ms: p(&lat, 0.99),
        dropped: r.published.len() - lat.len(),
        floor_p50_ms: p(&floor, 0.5),
        floor_p99_ms: p(&floor, 0.99),
        p90_ms: p(&lat, 0.9),
        max_ms: p(&lat, 1.0),
        floor_p90_ms: p(&floor, 0.9),
        floor_max_ms: p(&floor, 1.0),
        floor_dropped: r.published.len() - floor.len(),
        rate_hz: args.rate,
        seconds: args.seconds,
        width: 0,
        height: 0,
        publisher_late: r.publisher_late,
        rss_start_kb: rss_start,
        rss_end_kb: rss_end,
        rss_every_10s_kb: rss_samples,
    };
    Ok((report, line))
}

fn table(r: &Report) -> String {
    let kb = |v: Option<u64>| v.map_or_else(|| "?".to_owned(), |v| format!("{v} kB"));
    format!(
        "vref bench ros2: {} frames of {}x{} at {} Hz for {} s ({} sent late by the publisher)\n\
         {:<28} {:>8} {:>8} {:>8} {:>8} {:>8}\n\
         {:<28} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8}\n\
         {:<28} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8}\n\
         vref-ros2 resident memory: {} when warm, {} at the end (every 10 s: {:?} kB)\n",
        r.frames,
        r.width,
        r.height,
        r.rate_hz,
        r.seconds,
        r.publisher_late,
        "",
        "p50 ms",
        "p90 ms",
        "p99 ms",
        "max ms",
        "dropped",
        "stamp -> vref-ros2 markers",
        r.p50_ms,
        r.p90_ms,
        r.p99_ms,
        r.max_ms,
        r.dropped,
        "stamp -> rclpy relay (floor)",
        r.floor_p50_ms,
        r.floor_p90_ms,
        r.floor_p99_ms,
        r.floor_max_ms,
        r.floor_dropped,
        kb(r.rss_start_kb),
        kb(r.rss_end_kb),
        r.rss_every_10s_kb,
    )
}
