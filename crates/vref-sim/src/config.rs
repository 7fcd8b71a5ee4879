//! Every knob of the generator. Lengths are metres, angles degrees, colours
//! linear RGB reflectances in [0, 1]. A range `[lo, hi]` is drawn uniformly
//! per scene (integers inclusive).
//!
//! The world frame has its origin at the centre of the workspace, z up; the
//! support surface (table top or floor) is the plane z = 0.

use serde::{Deserialize, Serialize};

use crate::ConfigError;
use crate::appearance::MAX_VALUE_LEVELS;
use crate::shape::Shape;

/// The whole generator configuration. [`crate::Preset`] gives complete ones.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimConfig {
    pub workspace: WorkspaceSpec,
    /// The kinds of object that may stand in the workspace.
    pub classes: Vec<ClassSpec>,
    pub viewpoints: ViewpointSpec,
    /// The robot's RGB-D camera.
    pub robot: CameraSpec,
    /// The person's AR headset camera.
    pub human: CameraSpec,
    pub lighting: LightingSpec,
    pub features: FeatureSpec,
    /// Fewest objects each view must detect; layout and camera poses are
    /// redrawn until both views have this many.
    pub min_objects_per_view: usize,
    /// Most layouts and camera poses tried for one scene before giving up.
    pub attempts: usize,
}

/// Where objects may stand.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkspaceSpec {
    /// Size (x, y) of the rectangle, centred on the origin, that holds every
    /// object's footprint.
    pub area: [f64; 2],
    /// Least clearance between the footprint circles of two objects.
    pub min_gap: f64,
    /// Random positions tried per object before the layout is redrawn.
    pub placement_attempts: usize,
    /// How the support surface looks: seen where a segmentation mask bleeds
    /// past an object's outline.
    pub surface: Look,
}

/// One kind of object. Instances share the look up to `instance_variation`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClassSpec {
    pub name: String,
    pub shape: Shape,
    /// Standard deviation of the log of an instance's size factor.
    pub size_variation: f64,
    /// How many instances a scene holds, `[lo, hi]`.
    pub instances: [usize; 2],
    /// Standard deviation of the log of an instance's per-channel
    /// reflectance factor: how far look-alikes differ.
    pub instance_variation: f64,
    /// Looks of the vertical surface by sector around the object: `k`
    /// entries split the circle into `k` equal sectors, the first centred on
    /// the object's front (+x of its own frame), going counter-clockwise.
    /// One entry: the same from every side.
    pub sides: Vec<Look>,
    /// Look of the upward-facing surface.
    pub top: Look,
}

/// What a patch of surface looks like: colours by area, and the edges its
/// texture or print draws.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Look {
    pub patches: Vec<Patch>,
    pub edges: Vec<EdgeFamily>,
}

/// A colour covering a share of a surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Patch {
    /// Reflectance per channel.
    pub rgb: [f64; 3],
    /// Relative share of the surface (need not sum to 1).
    pub area: f64,
}

/// Edges of one direction drawn on a surface (print, seams, texture).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdgeFamily {
    /// Direction on the surface: 0 along the horizontal tangent (on a top
    /// surface: the object's x axis), 90 along the vertical one (top: y).
    pub angle_deg: f64,
    /// Edge contrast per unit area, relative to the other families.
    pub strength: f64,
}

/// Where the two cameras stand relative to each other.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewpointSpec {
    /// Azimuth of the robot camera around the workspace centre.
    pub robot_azimuth_deg: [f64; 2],
    /// Azimuth of the headset relative to the robot camera's (180: facing
    /// each other across the workspace).
    pub human_offset_deg: [f64; 2],
}

/// One camera: where it stands, what it can see, how it errs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    /// Horizontal distance from the workspace centre.
    pub distance: [f64; 2],
    /// Height above the support surface.
    pub height: [f64; 2],
    /// Standard deviation (per horizontal axis) of the point the camera is
    /// aimed at, around the workspace centre on the surface.
    pub aim_jitter: f64,
    /// Standard deviation of the roll about the optical axis (head tilt).
    pub roll_deg: f64,
    pub hfov_deg: f64,
    pub vfov_deg: f64,
    /// Image width in pixels; with `hfov_deg` it fixes the focal length,
    /// which sets how many pixels an object covers.
    pub image_width: u32,
    /// Nearest and farthest depth the sensor measures.
    pub depth_range: [f64; 2],
    /// An object is detected only if at least this share of its
    /// camera-facing surface (by pixels) is in the image and unoccluded.
    pub min_visible_fraction: f64,
    /// ... and only if it covers at least this many pixels.
    pub min_pixels: f64,
    /// Fixed per-channel colour response of this camera model.
    pub colour_gain: [f64; 3],
    pub noise: SensorNoise,
}

/// The errors of one camera's measurements. All zero: a perfect sensor
/// and segmentation (what remains are the effects of viewpoint, lighting
/// and occlusion on what is seen and how it looks).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorNoise {
    /// `k` of the depth error `sigma_z = k z^2` (1/m) of an object's
    /// centroid, as for stereo and structured light.
    pub depth: f64,
    /// Standard deviation of a per-frame relative depth scale error
    /// (calibration), stretching the whole view.
    pub depth_scale: f64,
    /// How far the reported position follows the centroid of the seen
    /// surface rather than the object's centre: 1 for a pipeline that
    /// averages its mask's depth pixels (it only sees the front), 0 for an
    /// ideal one that recovers the centre.
    pub surface_bias: f64,
    /// Standard deviation of the share of a mask's pixels that the
    /// segmentation gets wrong along one side of the outline: cut off, or
    /// taken from the background behind it.
    pub segmentation: f64,
    /// Histogram sampling noise relative to pure pixel-count statistics
    /// (`sqrt(p / pixels)` per bin); above 1 because neighbouring pixels are
    /// correlated.
    pub pixel: f64,
    /// Standard deviation of the log per-channel gain the auto white
    /// balance leaves uncorrected.
    pub white_balance: f64,
    /// Standard deviation of the log exposure.
    pub exposure: f64,
}

/// The scene's light.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightingSpec {
    /// Share of diffuse light that reaches every surface.
    pub ambient: f64,
    /// Elevation of the main light above the surface plane.
    pub elevation_deg: [f64; 2],
}

/// The appearance feature: a colour histogram followed by a
/// gradient-orientation histogram.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeatureSpec {
    /// Hue bins for saturated pixels, per brightness level.
    pub hue_bins: usize,
    /// Brightness levels of saturated pixels (1: hue only).
    pub value_levels: usize,
    /// Brightness bins for unsaturated (grey) pixels.
    pub grey_bins: usize,
    /// Unsigned gradient orientation bins over 180 degrees.
    pub orientation_bins: usize,
    /// L1 norm of the colour part.
    pub colour_weight: f64,
    /// L1 norm of the gradient part.
    pub gradient_weight: f64,
    /// Contrast of an object's outline against the background, relative to
    /// the edge strengths of its looks.
    pub outline_strength: f64,
}

impl FeatureSpec {
    /// Length of every feature vector.
    pub fn dim(&self) -> usize {
        self.hue_bins * self.value_levels + self.grey_bins + self.orientation_bins
    }
}

impl SimConfig {
    /// The same configuration with every sensor noise knob of both cameras
    /// at zero.
    pub fn noiseless(mut self) -> Self {
        self.robot.noise = SensorNoise::ZERO;
        self.human.noise = SensorNoise::ZERO;
        self
    }

    /// Refuses values the generator is not defined for, naming the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_workspace()?;
        if self.classes.is_empty() {
            return Err(invalid("classes", "at least one class is required"));
        }
        for (k, class) in self.classes.iter().enumerate() {
            class.validate(&format!("classes[{k}]"), self.workspace.area)?;
        }
        let least: usize = self.classes.iter().map(|c| c.instances[0]).sum();
        if least == 0 {
            return Err(invalid(
                "classes",
                "every scene needs an object: some class must have instances[0] >= 1",
            ));
        }
        let most: usize = self.classes.iter().map(|c| c.instances[1]).sum();
        let capacity = vref_scene::Limits::default().capacity;
        if most > capacity {
            return Err(invalid(
                "classes",
                format!("up to {most} objects, more than a graph's capacity of {capacity}"),
            ));
        }
        range(
            "viewpoints.robot_azimuth_deg",
            self.viewpoints.robot_azimuth_deg,
        )?;
        range(
            "viewpoints.human_offset_deg",
            self.viewpoints.human_offset_deg,
        )?;
        self.robot.validate("robot")?;
        self.human.validate("human")?;
        let light = &self.lighting;
        unit("lighting.ambient", light.ambient)?;
        range("lighting.elevation_deg", light.elevation_deg)?;
        if !(light.elevation_deg[0] >= 0.0 && light.elevation_deg[1] <= 90.0) {
            return Err(invalid("lighting.elevation_deg", "must lie within [0, 90]"));
        }
        self.features.validate()?;
        if self.min_objects_per_view == 0 {
            return Err(invalid("min_objects_per_view", "must be at least 1"));
        }
        if self.attempts == 0 {
            return Err(invalid("attempts", "must be at least 1"));
        }
        Ok(())
    }

    fn validate_workspace(&self) -> Result<(), ConfigError> {
        let ws = &self.workspace;
        for (axis, &size) in ws.area.iter().enumerate() {
            positive(&format!("workspace.area[{axis}]"), size)?;
        }
        non_negative("workspace.min_gap", ws.min_gap)?;
        if ws.placement_attempts == 0 {
            return Err(invalid(
                "workspace.placement_attempts",
                "must be at least 1",
            ));
        }
        ws.surface.validate("workspace.surface")
    }
}

impl ClassSpec {
    fn validate(&self, at: &str, area: [f64; 2]) -> Result<(), ConfigError> {
        if self.name.is_empty() {
            return Err(invalid(&format!("{at}.name"), "must not be empty"));
        }
        self.shape.validate(&format!("{at}.shape"))?;
        let footprint = 2.0 * self.shape.footprint_radius();
        if footprint > area[0].min(area[1]) {
            return Err(invalid(
                &format!("{at}.shape"),
                format!("footprint {footprint} m does not fit in the workspace area"),
            ));
        }
        // Beyond this an instance could be half or twice its class's size,
        // no longer "the same kind of object".
        if !(0.0..=0.3).contains(&self.size_variation) {
            return Err(invalid(
                &format!("{at}.size_variation"),
                "must lie in [0, 0.3]",
            ));
        }
        let [lo, hi] = self.instances;
        if lo > hi {
            return Err(invalid(
                &format!("{at}.instances"),
                format!("[{lo}, {hi}] is not a range"),
            ));
        }
        non_negative(&format!("{at}.instance_variation"), self.instance_variation)?;
        if self.sides.is_empty() {
            return Err(invalid(
                &format!("{at}.sides"),
                "at least one look is required",
            ));
        }
        for (k, look) in self.sides.iter().enumerate() {
            look.validate(&format!("{at}.sides[{k}]"))?;
        }
        self.top.validate(&format!("{at}.top"))
    }
}

impl Look {
    fn validate(&self, at: &str) -> Result<(), ConfigError> {
        if self.patches.is_empty() {
            return Err(invalid(
                &format!("{at}.patches"),
                "at least one patch is required",
            ));
        }
        for (k, patch) in self.patches.iter().enumerate() {
            for (c, &value) in patch.rgb.iter().enumerate() {
                unit(&format!("{at}.patches[{k}].rgb[{c}]"), value)?;
            }
            positive(&format!("{at}.patches[{k}].area"), patch.area)?;
        }
        for (k, edges) in self.edges.iter().enumerate() {
            finite(&format!("{at}.edges[{k}].angle_deg"), edges.angle_deg)?;
            non_negative(&format!("{at}.edges[{k}].strength"), edges.strength)?;
        }
        Ok(())
    }
}

impl CameraSpec {
    fn validate(&self, at: &str) -> Result<(), ConfigError> {
        range(&format!("{at}.distance"), self.distance)?;
        non_negative(&format!("{at}.distance[0]"), self.distance[0])?;
        range(&format!("{at}.height"), self.height)?;
        positive(&format!("{at}.height[0]"), self.height[0])?;
        non_negative(&format!("{at}.aim_jitter"), self.aim_jitter)?;
        non_negative(&format!("{at}.roll_deg"), self.roll_deg)?;
        for (name, fov) in [("hfov_deg", self.hfov_deg), ("vfov_deg", self.vfov_deg)] {
            if !(fov > 0.0 && fov < 180.0) {
                return Err(invalid(&format!("{at}.{name}"), "must lie in (0, 180)"));
            }
        }
        if self.image_width == 0 {
            return Err(invalid(&format!("{at}.image_width"), "must be at least 1"));
        }
        range(&format!("{at}.depth_range"), self.depth_range)?;
        positive(&format!("{at}.depth_range[0]"), self.depth_range[0])?;
        unit(
            &format!("{at}.min_visible_fraction"),
            self.min_visible_fraction,
        )?;
        non_negative(&format!("{at}.min_pixels"), self.min_pixels)?;
        for (c, &gain) in self.colour_gain.iter().enumerate() {
            positive(&format!("{at}.colour_gain[{c}]"), gain)?;
        }
        let n = &self.noise;
        for (name, value) in [
            ("depth", n.depth),
            ("depth_scale", n.depth_scale),
            ("surface_bias", n.surface_bias),
            ("segmentation", n.segmentation),
            ("pixel", n.pixel),
            ("white_balance", n.white_balance),
            ("exposure", n.exposure),
        ] {
            non_negative(&format!("{at}.noise.{name}"), value)?;
        }
        Ok(())
    }
}

impl SensorNoise {
    pub const ZERO: SensorNoise = SensorNoise {
        depth: 0.0,
        depth_scale: 0.0,
        surface_bias: 0.0,
        segmentation: 0.0,
        pixel: 0.0,
        white_balance: 0.0,
        exposure: 0.0,
    };
}

impl FeatureSpec {
    fn validate(&self) -> Result<(), ConfigError> {
        // Interpolating between neighbouring bins needs two of them.
        for (name, bins) in [
            ("hue_bins", self.hue_bins),
            ("grey_bins", self.grey_bins),
            ("orientation_bins", self.orientation_bins),
        ] {
            if !(2..=256).contains(&bins) {
                return Err(invalid(&format!("features.{name}"), "must lie in [2, 256]"));
            }
        }
        if !(1..=MAX_VALUE_LEVELS).contains(&self.value_levels) {
            return Err(invalid(
                "features.value_levels",
                format!("must lie in [1, {MAX_VALUE_LEVELS}]"),
            ));
        }
        non_negative("features.colour_weight", self.colour_weight)?;
        non_negative("features.gradient_weight", self.gradient_weight)?;
        non_negative("features.outline_strength", self.outline_strength)?;
        if self.colour_weight + self.gradient_weight <= 0.0 {
            return Err(invalid(
                "features",
                "colour_weight and gradient_weight cannot both be 0",
            ));
        }
        Ok(())
    }
}

pub(crate) fn invalid(field: &str, message: impl Into<String>) -> ConfigError {
    ConfigError::Invalid {
        field: field.to_owned(),
        message: message.into(),
    }
}

fn finite(field: &str, value: f64) -> Result<(), ConfigError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(invalid(field, format!("{value} is not a finite number")))
    }
}

pub(crate) fn positive(field: &str, value: f64) -> Result<(), ConfigError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("{value} must be positive and finite"),
        ))
    }
}

fn non_negative(field: &str, value: f64) -> Result<(), ConfigError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(invalid(field, format!("{value} must be finite and >= 0")))
    }
}

fn unit(field: &str, value: f64) -> Result<(), ConfigError> {
    if (0.0..=1.0).contains(&value) {
        Ok(())
    } else {
        Err(invalid(field, format!("{value} must lie in [0, 1]")))
    }
}

fn range(field: &str, [lo, hi]: [f64; 2]) -> Result<(), ConfigError> {
    if lo.is_finite() && hi.is_finite() && lo <= hi {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("[{lo}, {hi}] is not a finite range"),
        ))
    }
}
