use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use vref_match::{Method, Tier};
use vref_perception::NoiseSource;

/// vref: which object does the person mean? Graph matching of the robot's
/// and the AR headset's views of one workspace.
///
/// Exit codes: 0 success, 1 failure while running, 2 bad input (usage,
/// configuration or data); `vref query` also 3, 4, 5 for a bad_request,
/// not_ready or stale answer (vref query --help). Logs go to stderr; set RUST_LOG (e.g.
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
    /// views side by side (or, with --bop, both cameras' images), green
    /// lines where the match is right, red where it is wrong.
    Viz(VizArgs),
    /// Ask the running matcher which robot object a person means.
    ///
    /// The answer is printed whatever its status (with --json, one object
    /// whose `status` says what it is and `solved` whether a real solve
    /// made the answering solution, not one carried over unchanged).
    ///
    /// Exit codes: 0 an answer from the solution (ok, ambiguous, no_match);
    /// 1 no matcher (or no bridge) answered within --timeout, or another
    /// failure; 2 bad input (usage, configuration, endpoint, prefix);
    /// 3 bad_request (e.g. an unknown human object); 4 not_ready (no
    /// solution yet); 5 stale (the newest snapshots are older than
    /// [matcher] stale_after_ms).
    Query(QueryArgs),
    /// Run the three services with synthetic feeds (or BOP scenes: --source
    /// bop:DIR), point at known objects, check every answer against the
    /// truth, and print a summary.
    Demo(DemoArgs),
    /// Run the three services under load for a while (synthetic feeds at
    /// --feed-rate, queries at --query-rate) and report what was lost:
    /// snapshots published, received and rejected by reason; queries
    /// answered, by status, timed out; round trips p50/p99/p99.9/max; the
    /// matcher's resident memory after warm-up (first answer and first
    /// solve done) and at the end, so that growth means a leak. Exit code 1
    /// if a service dies.
    Soak(SoakArgs),
    /// Run the three services with synthetic feeds until interrupted
    /// (SIGINT, SIGTERM) or --for has passed, for clients to talk to:
    /// under an iceoryx2 root path and prefix of their own, whose
    /// configuration file is printed first (`config PATH`; connect with
    /// it, e.g. `vref query --config PATH --latest-gesture`), then `ready`
    /// once the matcher answers. Exit code 1 if a service dies.
    Up(UpArgs),
    /// Record what the feeds publish (snapshots of both views, pointing
    /// rays) into a file that a feed can replay (--source recording:FILE).
    /// FILE.mcap: an MCAP file with the raw wire messages on their own
    /// channels beside the Foxglove channels of `vref view`; any other
    /// name: vref's own bincode frames. Or, with --ros2 FILE.mcap,
    /// vref-ros2's outputs as ROS 2 messages (a rosbag2 file).
    Record(RecordArgs),
    /// See what the matcher decides, in Foxglove: both views' objects
    /// coloured by the matcher's decision, the pairs, the pointing ray and
    /// the latest answer, served live over the Foxglove WebSocket protocol
    /// (open ws://ADDR in Foxglove) and/or written to an MCAP file
    /// (docs/viewer.md). Subscribes only, plus --answer-rate latest-gesture
    /// queries of its own.
    View(ViewArgs),
    /// Publish one kind of malformed message into the running services
    /// (fault injection); an unknown kind lists the kinds.
    Inject(crate::inject::InjectArgs),
    /// Segment RGB-D frames into objects without masks: the class-agnostic
    /// segmenter (supporting plane, depth jumps, concave creases, colour
    /// edges; docs/perception.md, "Segmenter") writes a 16-bit label PNG
    /// per frame (0 background, 1..n the objects). One frame (--rgb,
    /// --depth, --camera, --out FILE.png) or every scene folder of DIR in
    /// the OSD layout (DIR/SCENE/{rgb,depth}.png, camera DIR/camera.json
    /// or DIR/../camera.json;
    /// --out a folder, written OUT/SCENE.png). A frame without a
    /// supporting plane gets an all-0 label image and its reason. A camera
    /// file that states a lens (distortion_model, d) has its frames
    /// rectified first: the labels are of the rectified image.
    Segment(SegmentArgs),
    /// Match two RGB-D frames, the robot's and the person's: each a frame
    /// folder (rgb.png, depth.png, optional masks.png, the nearest
    /// camera.json with fx, fy, cx, cy, width, height, depth_scale_mm and,
    /// for a lens that bends rays, distortion_model and d as ROS's
    /// CameraInfo: the frame is then rectified first, and labels and
    /// pixels are of the rectified image), segmented where it has no
    /// masks, measured, and matched by the [matcher] method (default
    /// rigid). Prints one answer per person-side object, with the status
    /// the live matcher would give it.
    ///
    /// Exit codes: 0 answered (whatever the statuses), 1 failure while
    /// running, 2 bad input (a file missing or unreadable, sizes that
    /// differ, depth not 16-bit or without any reading, intrinsics not
    /// finite and positive, a lens model it cannot rectify).
    Match(MatchArgs),
    /// Benchmarks that print percentiles (never pass/fail).
    #[command(subcommand)]
    Bench(BenchCommand),
    /// Print the wire contract for other languages (docs/wire.md): every
    /// shared-memory type's size, alignment, iceoryx2 type name and field
    /// offsets, sizes and types; the schema version and constants; the
    /// codes of enum and flag fields; and every service's name under the
    /// namespace with the settings it is created with. docs/wire-layout.json
    /// is the --json output with the default configuration.
    WireLayout(WireLayoutArgs),
}

#[derive(Debug, Args)]
pub struct WireLayoutArgs {
    /// Print one JSON object per line (the schema, then each type, each
    /// set of codes, each service; field `record` says which).
    #[arg(long)]
    pub json: bool,
    /// Service names under this namespace instead of the configuration's
    /// `[ipc] namespace`.
    #[arg(long, value_name = "NS")]
    pub namespace: Option<String>,
    /// Configuration file (its [ipc] section sizes the services: max_clients,
    /// max_subscribers, initial_objects).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
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
    /// confidence, status as the matcher would give it under the
    /// configuration's [matcher] settings, the pair's residual where
    /// tested, correct, matched, ...) as JSON Lines to FILE: the input of
    /// tools/fit-calibration.py.
    #[arg(long, value_name = "FILE.jsonl", requires = "dataset")]
    pub answers: Option<PathBuf>,
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml if
    /// present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("input").required(true).args(["dataset", "bop"])))]
pub struct VizArgs {
    /// Dataset file (JSON Lines, one scene pair per line).
    #[arg(long, value_name = "FILE.jsonl")]
    pub dataset: Option<PathBuf>,
    /// Instead of a dataset: a BOP dataset folder. The scene (named as
    /// `vref import bop` names it, e.g. table/000003) is measured by the
    /// perception front end and drawn over its two images (image 0 the
    /// robot's, image 1 the headset's): masks outlined, right pairs green,
    /// wrong red, objects without a partner crossed.
    #[arg(long, value_name = "DIR")]
    pub bop: Option<PathBuf>,
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
    /// Seed; the same preset, count and seed give a byte-identical file
    /// (the default, 1, is every command's: `vref bench solver` times
    /// these scenes).
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    /// Output dataset file, written whole or not at all (default: stdout).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Give each view its camera's up vector (gravity, camera frame),
    /// tilted by an error of DEG degrees (standard deviation), as a
    /// headset or robot estimates it; the scenes are otherwise the same.
    /// Not with --preset rigid.
    #[arg(long, value_name = "DEG")]
    pub up_vectors: Option<f64>,
}

#[derive(Debug, Subcommand)]
pub enum ImportCommand {
    /// CMU House landmarks (FGM layout: label/, adj/, scf/): human view =
    /// frame k, robot view = frame k + gap, positions (x, y, 0) in pixels.
    CmuHouse(CmuHouseArgs),
    /// A BOP dataset (RGB-D images, instance masks, ground-truth poses):
    /// one scene pair per scene, image --robot-image the robot's view,
    /// --human-image the headset's, objects measured by the perception
    /// front end ([perception] of the configuration), ground truth from
    /// the instance index (pairs where both views measured the object).
    /// A scene that cannot be read is skipped with a warning.
    Bop(BopArgs),
}

#[derive(Debug, Args)]
pub struct BopArgs {
    /// Dataset folder (holding SPLIT/SCENE/ folders); scene names are its
    /// name and the scene id, e.g. table/000003.
    pub dir: PathBuf,
    /// The split to read.
    #[arg(long, value_name = "NAME", default_value = "test")]
    pub split: String,
    /// Image id of the robot's view in every scene.
    #[arg(long, value_name = "ID", default_value_t = 0)]
    pub robot_image: u32,
    /// Image id of the headset's view in every scene.
    #[arg(long, value_name = "ID", default_value_t = 1)]
    pub human_image: u32,
    /// Skip masks with fewer pixels or depth readings (default:
    /// [perception] min_pixels).
    #[arg(long, value_name = "N")]
    pub min_pixels: Option<usize>,
    /// Measure vref's own segments instead of the dataset's masks: the
    /// segmenter ([segmentation]) on colour and depth; a segment's ground
    /// truth is the instance whose visible mask it overlaps with an IoU of
    /// 0.5 or more, else it has none.
    #[arg(long)]
    pub segment: bool,
    /// The up direction (against gravity) of the dataset's world frame,
    /// e.g. 0,0,1: each view then carries its camera's up vector from
    /// cam_R_w2c (BOP does not say which way its worlds stand; the
    /// rendered scenes of ../shared/data/bop stand on z). Default: none.
    #[arg(long, value_name = "X,Y,Z", value_parser = vref_measure::parse_direction)]
    pub world_up: Option<[f64; 3]>,
    /// Output dataset file, written whole or not at all (default: stdout).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml if
    /// present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
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
    /// Seed of the landmark choice and of the robot view's object order
    /// (the default, 1, is every command's).
    #[arg(long, value_name = "S", default_value_t = 1)]
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
        value_parser = six_numbers,
        allow_hyphen_values = true
    )]
    pub ray: Option<[f32; 6]>,
    /// The object the latest pointing gesture points at.
    #[arg(long)]
    pub latest_gesture: bool,
    /// Cone half-angle of `--ray`, radians.
    #[arg(long, value_name = "RAD", default_value_t = 0.1)]
    pub cone: f32,
    /// How long to wait for the answer, e.g. 1s, 300ms.
    #[arg(long, value_name = "D", default_value = "1s", value_parser = vref_measure::parse_duration)]
    pub timeout: std::time::Duration,
    /// The former spelling of --timeout, in milliseconds.
    #[arg(long, value_name = "MS", hide = true, conflicts_with = "timeout")]
    pub timeout_ms: Option<u64>,
    /// Print the answer as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Ask over Zenoh from another computer, through the robot's
    /// vref-bridge reachable at this endpoint (tcp/HOST:PORT), instead of
    /// the local matcher over shared memory.
    #[arg(long, value_name = "ENDPOINT")]
    pub remote: Option<String>,
    /// With --remote: the robot's key prefix, e.g. vref/robot1 (default:
    /// the configuration's [bridge] prefix).
    #[arg(long, value_name = "P", requires = "remote")]
    pub prefix: Option<String>,
    /// With --remote: how the query and answer travel, json or binary.
    #[arg(long, value_name = "E", default_value = "json", requires = "remote")]
    pub encoding: vref_bridge::Format,
    /// Configuration file (its [ipc] section says where the matcher is).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct RecordArgs {
    /// Output recording: FILE.mcap for MCAP (raw wire channels and
    /// Foxglove channels), any other name for vref's own bincode frames
    /// with timestamps (.vrec).
    #[arg(long, value_name = "FILE", required_unless_present = "ros2")]
    pub out: Option<PathBuf>,
    /// Instead of --out: record vref-ros2's outputs as ROS 2 messages
    /// into FILE.mcap (MCAP profile ros2, ros2msg schemas, CDR messages:
    /// what `ros2 bag play` and Foxglove read): the MarkerArray, the
    /// referenced object's PointStamped and the headset pose's PoseStamped,
    /// on the [ros2] topics, made from the matcher's snapshots, decisions
    /// and latest-gesture answers (docs/ros2.md). No DDS is started.
    #[arg(long, value_name = "FILE.mcap", conflicts_with_all = ["out", "images"])]
    pub ros2: Option<PathBuf>,
    /// How long to record, e.g. 10s, 500ms, 2m.
    #[arg(long, value_name = "D", value_parser = vref_measure::parse_duration)]
    pub duration: std::time::Duration,
    /// MCAP and --ros2 only: latest-gesture queries per second whose
    /// answers are recorded, on /vref/answer (MCAP; default 0: none, the
    /// recorder only subscribes) or as referenced objects (--ros2; default
    /// [ros2] answer_rate_hz).
    #[arg(long, value_name = "HZ", value_parser = rate_or_zero)]
    pub answer_rate: Option<f64>,
    /// MCAP only: also record the cameras' images, as `vref view --images`.
    #[arg(long, value_name = "bop:DIR", value_parser = images_source)]
    pub images: Option<PathBuf>,
    /// Configuration file (its [ipc] section says where the feeds are).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// What the feeds show: `synthetic` (the [feeds] world) or `bop:DIR`
    /// (the scenes of a BOP dataset folder or of a folder of them, measured
    /// by the perception front end; the person points from the headset at
    /// one object both views measured, another every half scene; no query
    /// in a target's first 0.5 s, while the new scene's snapshots arrive).
    #[arg(long, value_name = "SOURCE", default_value = "synthetic")]
    pub source: vref_feed::SourceSpec,
    /// BOP source: how long each scene is shown, e.g. 5s, 500ms.
    #[arg(long, value_name = "D", default_value = "5s", value_parser = vref_measure::parse_duration)]
    pub hold: std::time::Duration,
    /// The former spelling of --hold, in seconds.
    #[arg(long, value_name = "SECONDS", hide = true, conflicts_with = "hold", value_parser = positive_seconds)]
    pub hold_s: Option<f64>,
    /// BOP source: which way is up in the datasets' world frame, e.g.
    /// 0,0,1 (the feeds' --world-up): every snapshot carries its camera's
    /// up vector. Default: none.
    #[arg(long, value_name = "X,Y,Z", value_parser = vref_measure::parse_direction)]
    pub world_up: Option<[f64; 3]>,
    /// How long to query after the services are ready, e.g. 20s.
    #[arg(long, value_name = "D", default_value = "20s", value_parser = vref_measure::parse_duration)]
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
pub struct UpArgs {
    /// Objects in the synthetic world (default: drawn per class as the
    /// [feeds] preset says).
    #[arg(long, value_name = "N")]
    pub objects: Option<usize>,
    /// Stop after this long, e.g. 30s (default: only when interrupted).
    #[arg(long = "for", value_name = "D", value_parser = vref_measure::parse_duration)]
    pub duration: Option<std::time::Duration>,
    /// Configuration file; the services run under their own iceoryx2 root
    /// path and prefix whatever its [ipc] says.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct SoakArgs {
    /// How long to send queries after warm-up, e.g. 20s, 10m.
    #[arg(long, value_name = "D", default_value = "60s", value_parser = vref_measure::parse_duration)]
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
    /// One query's time limit, e.g. 1s, 500ms; a query without an answer
    /// by then counts as a timeout.
    #[arg(long, value_name = "D", default_value = "1s", value_parser = vref_measure::parse_duration)]
    pub timeout: std::time::Duration,
    /// The former spelling of --timeout, in milliseconds.
    #[arg(long, value_name = "MS", hide = true, conflicts_with = "timeout", value_parser = clap::value_parser!(u64).range(1..))]
    pub timeout_ms: Option<u64>,
    /// Print only the summary, as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Configuration file; the soak runs the services under its own
    /// iceoryx2 root path and prefix whatever its [ipc] says.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

impl QueryArgs {
    /// --timeout, or the hidden --timeout-ms if that was given.
    pub fn timeout(&self) -> std::time::Duration {
        self.timeout_ms
            .map_or(self.timeout, std::time::Duration::from_millis)
    }
}

impl SoakArgs {
    /// --timeout, or the hidden --timeout-ms if that was given.
    pub fn timeout(&self) -> std::time::Duration {
        self.timeout_ms
            .map_or(self.timeout, std::time::Duration::from_millis)
    }
}

impl DemoArgs {
    /// --hold in seconds, or the hidden --hold-s if that was given.
    pub fn hold_s(&self) -> f64 {
        self.hold_s.unwrap_or(self.hold.as_secs_f64())
    }
}

#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Serve the Foxglove WebSocket protocol on this address; port 0
    /// takes a free one. The address served is printed.
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:8765")]
    pub listen: std::net::SocketAddr,
    /// Serve nothing; only write --mcap.
    #[arg(long, requires = "mcap")]
    pub no_listen: bool,
    /// Write every channel to this MCAP file, with the raw wire messages
    /// (a feed can replay it: --source recording:FILE.mcap).
    #[arg(long, value_name = "FILE.mcap")]
    pub mcap: Option<PathBuf>,
    /// Stop after this long, e.g. 30s (default: on SIGINT/SIGTERM).
    #[arg(long, value_name = "D", value_parser = vref_measure::parse_duration)]
    pub duration: Option<std::time::Duration>,
    /// Most scene updates per second.
    #[arg(long, value_name = "HZ", default_value_t = 10.0, value_parser = positive_rate)]
    pub scene_rate: f64,
    /// Latest-gesture queries per second whose answers are shown (the
    /// viewer cannot see other clients' answers); 0: none.
    #[arg(long, value_name = "HZ", default_value_t = 2.0, value_parser = rate_or_zero)]
    pub answer_rate: f64,
    /// Also show the cameras' images when the feeds run on `--source
    /// bop:DIR` (give the same DIR and --config): each camera's colour
    /// image, its calibration and every object's mask outline coloured by
    /// the decision, for Foxglove's image panel (/vref/robot/image,
    /// /vref/human/image). Each image follows the scene its latest
    /// snapshot's track ids belong to.
    #[arg(long, value_name = "bop:DIR", value_parser = images_source)]
    pub images: Option<PathBuf>,
    /// Configuration file (its [ipc] section says where the services are).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

/// Six comma-separated numbers, as `--ray` takes them (one value, so
/// that `--help` names it once).
fn six_numbers(s: &str) -> Result<[f32; 6], String> {
    let numbers = s
        .split(',')
        .map(|v| {
            v.trim()
                .parse::<f32>()
                .map_err(|_| format!("`{v}` is not a number"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    numbers
        .try_into()
        .map_err(|n: Vec<f32>| format!("six numbers are needed, got {}", n.len()))
}

/// `bop:DIR`, the one images source so far (the form of the feeds'
/// `--source bop:DIR`, so that other sources can follow).
fn images_source(s: &str) -> Result<PathBuf, String> {
    match s.strip_prefix("bop:") {
        Some(dir) if !dir.is_empty() => Ok(PathBuf::from(dir)),
        _ => Err(format!("`{s}` is not bop:DIR")),
    }
}

fn rate_or_zero(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(0.0) => Ok(0.0),
        _ => positive_rate(s),
    }
}

fn positive_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a positive number of seconds")),
    }
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
    /// Query a matcher that is already running (its [ipc] settings from
    /// --config) with a Rust ReferenceClient, one latest-gesture query at a
    /// time at --rate, and print round-trip percentiles of answers from a
    /// solution an earlier answer came from and of the first answer from
    /// each new solution. `python -m
    /// vref_client.bench` runs it beside the Python client on the same
    /// matcher.
    Client(BenchClientArgs),
    /// Run the matcher, both feeds and vref-bridge (synthetic world, under
    /// a root path, prefix and loopback port of their own), and send
    /// reference queries at --rate both ways in the same run: over Zenoh
    /// through the bridge (as a controller on another computer would) and
    /// over iceoryx2 to the matcher directly; and a third way to a bare
    /// Zenoh queryable in this process that answers at once (Zenoh's own
    /// round trip, the floor under the bridge). Prints the round-trip
    /// percentiles of each and what the bridge adds.
    Remote(BenchRemoteArgs),
    /// Draw solve time against object count (log-log) from the JSON lines
    /// of `vref bench solver --json` and of tools/pygmtools_bench.py
    /// --json: one curve per method and tier, one per pygmtools method.
    Plot(BenchPlotArgs),
    /// Time the perception front end per image on BOP datasets (each
    /// scene's robot and headset image, decoded once, measured --repeats
    /// times): median and p99 of the front end alone, and of decoding one
    /// image's files (colour, depth, every mask) apart.
    Perception(BenchPerceptionArgs),
    /// Time the segmenter per frame on a folder of scene folders (OSD
    /// layout), single thread, images decoded beforehand: median and p99
    /// over --repeats passes; where a scene has a ground-truth label.png,
    /// score it by ../shared/data/osd/PROVENANCE.md's protocol (Hungarian
    /// pairing on Dice; overlap and boundary P/R/F, %75), averaged over
    /// scenes, overall and per group (OSD learn scene kinds, and the
    /// held-aside scenes whose number is 0 mod 5 against the rest).
    Segment(BenchSegmentArgs),
    /// Capture stamp to MarkerArray arrival through a real ROS 2 peer: an
    /// rclpy node publishes one RGB-D frame (--frame) at --rate as a camera
    /// driver would (rgb8, 16UC1, CameraInfo, a fresh stamp per frame) to
    /// vref-ros2 and a matcher started here, and times each frame's
    /// markers; a trivial rclpy relay receiving the same images gives the
    /// bare DDS floor in the same run. Runs itself in a network namespace
    /// with loopback only (unshare --net: root, util-linux, iproute2).
    /// Prints frames, p50/p90/p99/max (nearest rank), dropped frames,
    /// the floor's, and vref-ros2's resident memory when warm and at the
    /// end (docs/ros2.md).
    Ros2(BenchRos2Args),
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
    /// Also run `vref view` (its server listening on a free loopback port,
    /// writing an MCAP file of everything) on the services measured, to
    /// see what viewing costs the matcher's query path.
    #[arg(long)]
    pub with_viewer: bool,
    /// Ticks per second; each tick sends two matcher queries and one echo
    /// query.
    #[arg(long, value_name = "HZ", default_value_t = 200.0, value_parser = positive_rate)]
    pub rate: f64,
    /// How long to measure once the services answer, e.g. 30s.
    #[arg(long, value_name = "D", default_value = "10s", value_parser = vref_measure::parse_duration)]
    pub duration: std::time::Duration,
    /// Print one JSON object: objects, all_/cached_/solve_/bare_ p50, p99
    /// and p999 in microseconds, ratio_all_p99 (all matcher answers' p99 /
    /// bare p99), ratio_p99 (cached p99 / bare p99), counts.
    #[arg(long)]
    pub json: bool,
    /// First measure as long with an idle matcher (both feeds running but
    /// publishing under a namespace the matcher does not hear: the same
    /// feed load, no snapshot, no solve), then with the feeds heard, and
    /// report both: idle_all_p50_us, idle_all_p99_us, ratio_busy_idle_p99,
    /// and the matcher's solve times from its decisions.
    #[arg(long)]
    pub compare_idle: bool,
    /// Configuration file ([matcher] method, [feeds] rates and preset);
    /// the services run under their own iceoryx2 root path and prefix
    /// whatever its [ipc] says.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("input").required(true).args(["dir", "rgb"])))]
pub struct SegmentArgs {
    /// A folder of scene folders (OSD layout: SCENE/rgb.png,
    /// SCENE/depth.png; camera.json beside them).
    #[arg(value_name = "DIR", conflicts_with_all = ["rgb", "depth"])]
    pub dir: Option<PathBuf>,
    /// One frame's colour image (8-bit RGB).
    #[arg(long, value_name = "FILE", requires_all = ["depth", "camera"])]
    pub rgb: Option<PathBuf>,
    /// One frame's depth image (16-bit grey, registered to the colour
    /// image, 0 = no reading).
    #[arg(long, value_name = "FILE", requires = "rgb")]
    pub depth: Option<PathBuf>,
    /// Camera file: {"fx", "fy", "cx", "cy", "depth_scale_mm" (millimetres
    /// per depth unit, default 1), optional "width", "height"}. Default
    /// with DIR: DIR/camera.json, else DIR/../camera.json (OSD keeps it
    /// beside learn/).
    #[arg(long, value_name = "FILE")]
    pub camera: Option<PathBuf>,
    /// The label PNG to write (one frame), or the folder to write
    /// SCENE.png into (DIR; created if missing).
    #[arg(long, value_name = "PATH")]
    pub out: PathBuf,
    /// Also draw the labels over the colour image: a PNG (one frame) or a
    /// folder of SCENE.png (DIR).
    #[arg(long, value_name = "PATH")]
    pub overlay: Option<PathBuf>,
    /// Print one JSON object per frame (scene, objects, no_support, out).
    #[arg(long)]
    pub json: bool,
    /// The thresholds: `frame` scales [segmentation] (set for a Kinect)
    /// for the depth noise each frame shows, measured on it (a noisier
    /// camera's thresholds grow with the root of its noise; a quieter
    /// one's stay); `config` takes [segmentation] as it is.
    #[arg(long, value_name = "frame|config", default_value_t = NoiseSource::Frame)]
    pub noise: NoiseSource,
    /// Configuration file (its [segmentation] section; default:
    /// $VREF_CONFIG, else config/vref.toml if present, else built-in
    /// defaults).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct MatchArgs {
    /// The robot camera's frame folder.
    #[arg(value_name = "ROBOT_DIR")]
    pub robot: PathBuf,
    /// The person's (headset) camera's frame folder.
    #[arg(value_name = "HUMAN_DIR")]
    pub human: PathBuf,
    /// Print one JSON object per person-side object: human_label,
    /// robot_label (or null), status (ok, ambiguous, no_match),
    /// confidence, centroid_px [u, v] and position [x, y, z] (metres,
    /// the person's camera frame).
    #[arg(long)]
    pub json: bool,
    /// Write the labels the answers name: DIR/robot.png and DIR/human.png
    /// (16-bit, 0 background; created if missing).
    #[arg(long, value_name = "DIR")]
    pub labels_out: Option<PathBuf>,
    /// Draw the match over both images (person left, robot right; masks
    /// outlined; lines green ok, orange ambiguous; blue: no partner) as a PNG.
    #[arg(long, value_name = "FILE")]
    pub viz: Option<PathBuf>,
    /// Matching method (default: [matcher] method).
    #[arg(long, value_name = "NAME", value_parser = parse_method)]
    pub method: Option<Method>,
    /// Each camera's per-reading depth noise: `frame` measures it on the
    /// frame itself (second differences of neighbouring readings; the
    /// configured law where a frame has too little depth), `config` takes
    /// [perception.robot] and [perception.human] `pixel` (the rendered
    /// BOP cameras by default). It sets the segmenter's thresholds and the
    /// objects' stated errors; the systematic part is always configured.
    #[arg(long, value_name = "frame|config", default_value_t = NoiseSource::Frame)]
    pub noise: NoiseSource,
    /// Configuration file ([matcher], [matching], [perception],
    /// [segmentation]; default: $VREF_CONFIG, else config/vref.toml if
    /// present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct BenchSegmentArgs {
    /// A folder of scene folders (OSD layout: SCENE/rgb.png,
    /// SCENE/depth.png, optional SCENE/label.png; camera.json beside
    /// them).
    #[arg(long, value_name = "DIR")]
    pub dataset: PathBuf,
    /// Camera file (default: DIR/camera.json, else DIR/../camera.json).
    #[arg(long, value_name = "FILE")]
    pub camera: Option<PathBuf>,
    /// Times each frame is segmented (timings over all of them).
    #[arg(long, value_name = "N", default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..))]
    pub repeats: u64,
    /// Ground-truth labels at or above this are objects (OSD: 20; below
    /// are the table and no reading).
    #[arg(long, value_name = "L", default_value_t = 20)]
    pub first_object: u16,
    /// Print one JSON object per line: with --scenes each scene's scores,
    /// then the summary ({"images", "median_us", "p99_us", "overlap_f",
    /// "boundary_f", "p75", ..., "groups": [...]}).
    #[arg(long)]
    pub json: bool,
    /// Also print each scene's scores.
    #[arg(long)]
    pub scenes: bool,
    /// Configuration file (its [segmentation] section).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct BenchPerceptionArgs {
    /// A BOP dataset folder, or a folder of them (one result each).
    #[arg(long, value_name = "DIR")]
    pub dataset: PathBuf,
    /// The split to read.
    #[arg(long, value_name = "NAME", default_value = "test")]
    pub split: String,
    /// Image id of the robot's view.
    #[arg(long, value_name = "ID", default_value_t = 0)]
    pub robot_image: u32,
    /// Image id of the headset's view.
    #[arg(long, value_name = "ID", default_value_t = 1)]
    pub human_image: u32,
    /// Timed passes over every image.
    #[arg(long, value_name = "N", default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..))]
    pub repeats: u64,
    /// Print one JSON object per dataset: dataset, images, objects,
    /// max_masks, median_us, p99_us, decode_median_us, decode_p99_us,
    /// repeats.
    #[arg(long)]
    pub json: bool,
    /// Configuration file ([perception] settings).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct BenchRos2Args {
    /// How long to measure once vref-ros2 answers, in seconds (60 for the
    /// memory and drop figures).
    #[arg(long, value_name = "S", default_value_t = 10.0, value_parser = positive_rate)]
    pub seconds: f64,
    /// Frames per second the peer publishes.
    #[arg(long, value_name = "HZ", default_value_t = 30.0, value_parser = positive_rate)]
    pub rate: f64,
    /// The RGB-D frame folder published (rgb.png, depth.png, the nearest
    /// camera.json), segmented by vref-ros2 each time.
    #[arg(
        long,
        value_name = "DIR",
        default_value = "../shared/data/osd/learn/learn3"
    )]
    pub frame: PathBuf,
    /// Python with rclpy (default: $VREF_ROS2_PYTHON; tools/test.sh
    /// installs one in target/ros2-venv).
    #[arg(long, value_name = "FILE")]
    pub python: Option<PathBuf>,
    /// Print one JSON object: frames, p50_ms, p99_ms, dropped,
    /// floor_p50_ms, floor_p99_ms, then p90_ms, max_ms, floor_p90_ms,
    /// floor_max_ms, floor_dropped, rate_hz, seconds, width, height,
    /// publisher_late, rss_start_kb, rss_end_kb, rss_every_10s_kb.
    #[arg(long)]
    pub json: bool,
    /// Configuration file ([ros2], [segmentation], [perception]; [ipc] is
    /// replaced by an isolated one).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Set when the command has re-run itself in its namespace.
    #[arg(long, hide = true)]
    pub inside_namespace: bool,
}

#[derive(Debug, Args)]
pub struct BenchClientArgs {
    /// Queries per second, one at a time.
    #[arg(long, value_name = "HZ", default_value_t = 200.0, value_parser = positive_rate)]
    pub rate: f64,
    /// How long to measure once the matcher answers, e.g. 10s.
    #[arg(long, value_name = "D", default_value = "10s", value_parser = vref_measure::parse_duration)]
    pub duration: std::time::Duration,
    /// How long to wait for a first ok or ambiguous answer, e.g. 30s.
    #[arg(long, value_name = "D", default_value = "30s", value_parser = vref_measure::parse_duration)]
    pub ready_within: std::time::Duration,
    /// Print one JSON object: cached_/solve_ p50 and p99 in microseconds,
    /// counts, timeouts, errors.
    #[arg(long)]
    pub json: bool,
    /// Configuration file (its [ipc] section says where the matcher is).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct BenchRemoteArgs {
    /// Objects in the synthetic world.
    #[arg(long, value_name = "N", default_value_t = 32)]
    pub objects: usize,
    /// Ticks per second; each tick sends one query each way (bridge,
    /// bare Zenoh echo, local iceoryx2), in rotating order.
    #[arg(long, value_name = "HZ", default_value_t = 200.0, value_parser = positive_rate)]
    pub rate: f64,
    /// How long to measure once both answer, e.g. 10s.
    #[arg(long, value_name = "D", default_value = "10s", value_parser = vref_measure::parse_duration)]
    pub duration: std::time::Duration,
    /// How remote queries and answers travel: json or binary.
    #[arg(long, value_name = "E", default_value = "binary")]
    pub encoding: vref_bridge::Format,
    /// Print one JSON object: remote_, local_ and zenoh_ (the bare echo)
    /// p50 and p99 in microseconds, added_p50_us and added_p99_us (remote
    /// minus local), bridge_over_zenoh_ (remote minus echo), counts.
    #[arg(long)]
    pub json: bool,
    /// Configuration file ([matcher] method, [feeds] rates and preset);
    /// the services run under their own iceoryx2 root path and prefix, the
    /// bridge on a loopback port of its own, whatever it says.
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
    /// Standard deviation of the robot view's position noise per axis,
    /// metres. The default's scenes are settled by the first right motion;
    /// noise near the objects' spacing (about 0.02 at 64 objects) makes
    /// `rigid` run its whole search.
    #[arg(long, value_name = "METRES", default_value_t = vref_sim::RigidScene::POSITION_NOISE)]
    pub noise: f64,
    /// Both views carry their up vectors (exact: the motion turns the
    /// human view's up into the robot's), as `rigid` uses them.
    #[arg(long)]
    pub up_vectors: bool,
    /// Print one JSON object per method, size and mode instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Configuration file (its [matching] section gives beta and the
    /// methods' constants).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}
