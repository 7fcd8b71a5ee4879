use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use vref_match::{Method, Tier};

/// vref: which object does the person mean? Graph matching of the robot's
/// and the AR headset's views of one workspace.
///
/// Exit codes: 0 success, 1 failure while running, 2 bad input (usage,
/// configuration or data). Logs go to stderr; set RUST_LOG (e.g.
/// RUST_LOG=info) for more.
#[derive(Debug, Parser)]
#[command(name = "vref", version)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Evaluate matching methods on a dataset file (accuracy, precision,
    /// recall, mean solve time), or on generated scenes against a noise
    /// level (--sweep), with a plot.
    Eval(EvalArgs),
    /// Convert a public data set into a vref dataset file.
    #[command(subcommand)]
    Import(ImportCommand),
    /// Work with configuration files.
    #[command(subcommand)]
    Config(ConfigCommand),
    /// Generate synthetic scene pairs: one workspace seen by the robot's
    /// camera and the headset, as a dataset file with ground truth.
    Scenes(ScenesArgs),
    /// Draw one scene's predicted correspondences as a PNG picture: both
    /// views side by side, green lines where the match is right, dashed
    /// red where it is wrong.
    Viz(VizArgs),
    /// Ask the running matcher which robot object a person means.
    Query(QueryArgs),
    /// Run the three services with synthetic feeds, point at known objects,
    /// check every answer against the truth, and print a summary.
    Demo(DemoArgs),
    /// Run the three services under load for a while (synthetic feeds at
    /// --feed-rate, queries at --query-rate) and report what was lost:
    /// snapshots published, received and rejected by reason; queries
    /// answered, by status, timed out; round trips p50/p99/p99.9/max; the
    /// matcher's resident memory after warm-up (first answer and first
    /// solve done) and at the end, so that growth means a leak. Exit code 1
    /// if a service dies.
    Soak(SoakArgs),
    /// Record what the feeds publish (snapshots of both views, pointing
    /// rays) into a file that a feed can replay (--source recording:FILE).
    Record(RecordArgs),
    /// Publish one kind of malformed message into the running services
    /// (fault injection); an unknown kind lists the kinds.
    Inject(crate::inject::InjectArgs),
    /// Benchmarks that print percentiles (never pass/fail).
    #[command(subcommand)]
    Bench(BenchCommand),
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("input").required(true).args(["dataset", "sweep"])))]
pub struct EvalArgs {
    /// Dataset file (JSON Lines, one scene pair per line).
    #[arg(long, value_name = "FILE.jsonl")]
    pub dataset: Option<PathBuf>,
    /// Instead of a dataset: generate scenes of --preset with one kind of
    /// sensor noise scaled by each of --levels and plot accuracy against
    /// it to --out. depth-noise scales the depth error and the depth scale
    /// error of both cameras; feature-noise the histogram pixel noise,
    /// white balance and exposure errors (positions unchanged).
    #[arg(long, value_name = "KIND", requires_all = ["preset", "out"], value_parser = parse_sweep)]
    pub sweep: Option<vref_sim::NoiseSweep>,
    /// Scene family of the sweep: moi or mrc (as `vref scenes`).
    #[arg(long, value_name = "NAME", requires = "sweep")]
    pub preset: Option<String>,
    /// Sweep: the accuracy plot to write (PNG).
    #[arg(long, value_name = "FILE.png", requires = "sweep")]
    pub out: Option<PathBuf>,
    /// Sweep: scenes per level [default: 30].
    #[arg(long, value_name = "N", requires = "sweep")]
    pub count: Option<u64>,
    /// Sweep: seed of the scenes, the same at every level [default: 1].
    #[arg(long, value_name = "S", requires = "sweep")]
    pub seed: Option<u64>,
    /// Sweep: factors on the preset's noise [default: 0,0.5,1,2,4].
    #[arg(
        long,
        value_name = "L1,L2,...",
        value_delimiter = ',',
        requires = "sweep",
        allow_negative_numbers = true
    )]
    pub levels: Option<Vec<f64>>,
    /// Method to evaluate; repeat for several. Default: all of them
    /// (appearance, sm, rrwm, paper, rigid, clipper).
    #[arg(long = "method", value_name = "NAME", value_parser = parse_method)]
    pub methods: Vec<Method>,
    /// Spatial bandwidth beta, overriding the configuration (CMU House in
    /// pixels: 2500).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    pub beta: Option<f64>,
    /// Solver tier: exact (ALGORITHMS.md) or live (the matcher's shortcuts:
    /// candidate pairs pruned by appearance, early stop; each scene cold).
    #[arg(long, value_name = "TIER", value_parser = parse_tier, default_value = "exact")]
    pub tier: Tier,
    /// Print one JSON object per method on stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write every human object's answer (method, scene, row,
    /// confidence, correct, matched) as JSON Lines to FILE: the input of
    /// tools/fit-calibration.py.
    #[arg(long, value_name = "FILE.jsonl", requires = "dataset")]
    pub answers: Option<PathBuf>,
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml if
    /// present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct VizArgs {
    /// Dataset file (JSON Lines, one scene pair per line).
    #[arg(long, value_name = "FILE.jsonl")]
    pub dataset: PathBuf,
    /// Name of the scene to draw.
    #[arg(long, value_name = "NAME")]
    pub scene: String,
    /// Matching method (appearance, sm, rrwm, paper).
    #[arg(long, value_name = "NAME", value_parser = parse_method)]
    pub method: Method,
    /// Output picture (PNG).
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
    /// Spatial bandwidth beta, overriding the configuration (CMU House in
    /// pixels: 2500).
    #[arg(long, value_name = "B")]
    pub beta: Option<f64>,
    /// How positions are flattened: pixels (x, y), perspective (x/z, y/z),
    /// top-down (x, z), or auto (pixels if every z of a view is the same,
    /// else perspective if all are in front of the camera, else top-down).
    #[arg(long, value_name = "P", default_value = "auto", value_parser = parse_projection)]
    pub projection: vref_viz::Projection,
    /// Picture width in pixels.
    #[arg(long, value_name = "PX", default_value_t = 1200)]
    pub width: u32,
    /// Picture height in pixels.
    #[arg(long, value_name = "PX", default_value_t = 600)]
    pub height: u32,
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml if
    /// present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct ScenesArgs {
    /// Scene family: moi (table top, look-alike objects close together,
    /// cameras under 1 m away), mrc (floor area seen from 3-5 m, mostly
    /// identical cartons), or rigid (the scenes `vref bench solver` times:
    /// exactly --objects per view, all seen by both, 48-d features; scene k
    /// is the benchmark's scene of seed S + k).
    #[arg(long, value_name = "NAME")]
    pub preset: String,
    /// Objects per view of --preset rigid.
    #[arg(long, value_name = "N")]
    pub objects: Option<usize>,
    /// Number of scene pairs, at least 1. Scene k is the same whatever the
    /// count, so a shorter run is a prefix of a longer one.
    #[arg(long, value_name = "N")]
    pub count: u64,
    /// Seed; the same preset, count and seed give a byte-identical file.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Output dataset file, written whole or not at all (default: stdout).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
pub enum ImportCommand {
    /// CMU House landmarks (FGM layout: label/, adj/, scf/): human view =
    /// frame k, robot view = frame k + gap, positions (x, y, 0) in pixels.
    CmuHouse(CmuHouseArgs),
}

#[derive(Debug, Args)]
pub struct CmuHouseArgs {
    /// Directory holding label/, adj/ and scf/.
    pub dir: PathBuf,
    /// Frame gap between the human and the robot view.
    #[arg(long, value_name = "G")]
    pub gap: usize,
    /// Keep only each frame's Delaunay edges (default: fully connected).
    #[arg(long)]
    pub delaunay: bool,
    /// Use the shape contexts as appearance features (default: none).
    #[arg(long)]
    pub features: bool,
    /// Keep K random landmarks per frame, chosen independently per view,
    /// so that some objects have no partner.
    #[arg(long, value_name = "K")]
    pub keep: Option<usize>,
    /// Seed of the landmark choice and of the robot view's object order.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Output dataset file (default: stdout).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
pub enum ConfigCommand {
    /// Validate a configuration file; exit 2 naming the first problem.
    Check(ConfigCheckArgs),
}

#[derive(Debug, Args)]
pub struct ConfigCheckArgs {
    /// The file to check.
    pub file: PathBuf,
}

fn parse_method(s: &str) -> Result<Method, String> {
    s.parse().map_err(|e: vref_match::MatchError| e.to_string())
}

fn parse_tier(s: &str) -> Result<Tier, String> {
    s.parse().map_err(|e: vref_match::MatchError| e.to_string())
}

fn parse_sweep(s: &str) -> Result<vref_sim::NoiseSweep, String> {
    s.parse().map_err(|e: vref_sim::SweepError| e.to_string())
}

fn parse_projection(s: &str) -> Result<vref_viz::Projection, String> {
    s.parse()
        .map_err(|e: vref_viz::UnknownProjection| e.to_string())
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("target").required(true).args(["human_object", "ray", "latest_gesture"])))]
pub struct QueryArgs {
    /// The human-view object's track id.
    #[arg(long, value_name = "ID")]
    pub human_object: Option<u64>,
    /// A pointing ray in the human view's frame: origin and direction,
    /// metres (x right, y down, z forward).
    #[arg(
        long,
        value_name = "OX,OY,OZ,DX,DY,DZ",
        value_delimiter = ',',
        num_args = 6,
        allow_negative_numbers = true
    )]
    pub ray: Option<Vec<f32>>,
    /// The object the latest pointing gesture points at.
    #[arg(long)]
    pub latest_gesture: bool,
    /// Cone half-angle of `--ray`, radians.
    #[arg(long, value_name = "RAD", default_value_t = 0.1)]
    pub cone: f32,
    /// How long to wait for the answer, milliseconds.
    #[arg(long, value_name = "MS", default_value_t = 1000)]
    pub timeout_ms: u64,
    /// Print the answer as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Configuration file (its [ipc] section says where the matcher is).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct RecordArgs {
    /// Output recording (bincode frames with timestamps).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// How long to record, e.g. 10s, 500ms, 2m.
    #[arg(long, value_name = "D", value_parser = crate::duration::parse_duration)]
    pub duration: std::time::Duration,
    /// Configuration file (its [ipc] section says where the feeds are).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// How long to query after the services are ready, e.g. 20s.
    #[arg(long, value_name = "D", default_value = "20s", value_parser = crate::duration::parse_duration)]
    pub duration: std::time::Duration,
    /// Objects in the synthetic world (default: drawn per class as the
    /// [feeds] preset says).
    #[arg(long, value_name = "N")]
    pub objects: Option<usize>,
    /// Queries per second.
    #[arg(long, value_name = "HZ", default_value_t = 5.0, value_parser = positive_rate)]
    pub query_rate: f64,
    /// Print only the summary, as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Configuration file; the demo runs the services under its own
    /// iceoryx2 root path and prefix whatever its [ipc] says.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct SoakArgs {
    /// How long to send queries after warm-up, e.g. 20s, 10m.
    #[arg(long, value_name = "D", default_value = "60s", value_parser = crate::duration::parse_duration)]
    pub duration: std::time::Duration,
    /// Objects in the synthetic world (default: drawn per class as the
    /// [feeds] preset says).
    #[arg(long, value_name = "N")]
    pub objects: Option<usize>,
    /// Snapshots per second of each feed.
    #[arg(long, value_name = "HZ", default_value_t = 100.0, value_parser = positive_rate)]
    pub feed_rate: f64,
    /// Queries per second, one at a time (a query that takes longer than
    /// the period delays the next).
    #[arg(long, value_name = "HZ", default_value_t = 500.0, value_parser = positive_rate)]
    pub query_rate: f64,
    /// One query's time limit, milliseconds; a query without an answer by
    /// then counts as a timeout.
    #[arg(long, value_name = "MS", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(1..))]
    pub timeout_ms: u64,
    /// Print only the summary, as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Configuration file; the soak runs the services under its own
    /// iceoryx2 root path and prefix whatever its [ipc] says.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

fn positive_rate(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 1000.0 => Ok(v),
        _ => Err(format!("`{s}` is not a rate in (0, 1000]")),
    }
}

#[derive(Debug, Subcommand)]
pub enum BenchCommand {
    /// Time the matching methods on synthetic rigid scenes of exactly N
    /// objects per view (random positions in a 0.6 x 0.4 x 0.2 m box, the
    /// robot view a rigid motion plus 2 mm noise, 48-d features): median
    /// and p99 of a full solve (affinities, solve, Hungarian) and of the
    /// solve after one object moved ("incremental": the matcher engine's
    /// update by track id and its next solve), and the median iteration
    /// count.
    Solver(BenchSolverArgs),
    /// Run the matcher and both feeds (synthetic world, snapshots at the
    /// [feeds] rate) under a root path and prefix of their own, send
    /// reference queries at --rate, and print round-trip percentiles of
    /// answers from the cached solution and of answers that needed a
    /// solve, beside the bare iceoryx2 request/response round trip to an
    /// echo server measured in the same run with the same client, and
    /// their ratio. Each tick asks the matcher twice and the echo once, in
    /// rotating order.
    Query(BenchQueryArgs),
    /// Draw solve time against object count (log-log) from the JSON lines
    /// of `vref bench solver --json` and of tools/pygmtools_bench.py
    /// --json: one curve per method and tier, one per pygmtools method.
    Plot(BenchPlotArgs),
    /// The echo server of `vref bench query` (started by it): answers
    /// every reference query at once, under the namespace
    /// `<[ipc] namespace>/bench-echo`.
    #[command(hide = true)]
    EchoServer(EchoServerArgs),
}

#[derive(Debug, Args)]
pub struct BenchQueryArgs {
    /// Objects in the synthetic world (each view sees most of them).
    #[arg(long, value_name = "N", default_value_t = 32)]
    pub objects: usize,
    /// Ticks per second; each tick sends two matcher queries and one echo
    /// query.
    #[arg(long, value_name = "HZ", default_value_t = 200.0, value_parser = positive_rate)]
    pub rate: f64,
    /// How long to measure once the services answer, e.g. 30s.
    #[arg(long, value_name = "D", default_value = "10s", value_parser = crate::duration::parse_duration)]
    pub duration: std::time::Duration,
    /// Print one JSON object: objects, cached_/solve_/bare_ p50, p99 and
    /// p999 in microseconds, ratio_p99 (cached p99 / bare p99), counts.
    #[arg(long)]
    pub json: bool,
    /// Configuration file ([matcher] method, [feeds] rates and preset);
    /// the services run under their own iceoryx2 root path and prefix
    /// whatever its [ipc] says.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct BenchPlotArgs {
    /// Output of `vref bench solver --json`; repeat for several files
    /// (tiers, methods).
    #[arg(long, value_name = "FILE", required = true)]
    pub solver: Vec<PathBuf>,
    /// Output of `tools/pygmtools_bench.py --json` (its total_median_us:
    /// affinity matrix and solve); repeat for several.
    #[arg(long, value_name = "FILE")]
    pub pygmtools: Vec<PathBuf>,
    /// Which of vref's timings: full or incremental.
    #[arg(long, value_name = "MODE", default_value = "full")]
    pub mode: String,
    /// The picture to write (PNG).
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
}

#[derive(Debug, Args)]
pub struct EchoServerArgs {
    /// Configuration file (its [ipc] section says where to serve).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct BenchSolverArgs {
    /// Objects per view.
    #[arg(
        long,
        value_name = "N1,N2,...",
        value_delimiter = ',',
        default_value = "8,16,32,64"
    )]
    pub sizes: Vec<usize>,
    /// Method to time; repeat for several. Default: all of them.
    #[arg(long = "method", value_name = "NAME", value_parser = parse_method)]
    pub methods: Vec<Method>,
    /// Solver tier; repeat for both: exact (the definitions of
    /// ALGORITHMS.md) or live (candidate pairs pruned by appearance, early
    /// stop, warm start: what the matcher serves). Default: exact.
    #[arg(long = "tier", value_name = "TIER", value_parser = parse_tier)]
    pub tiers: Vec<Tier>,
    /// Timed solves per method, size and mode.
    #[arg(long, value_name = "N", default_value_t = 20)]
    pub repeats: usize,
    /// Seed of the scenes.
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    /// Print one JSON object per method, size and mode instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Configuration file (its [matching] section gives beta and the
    /// methods' constants).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}
