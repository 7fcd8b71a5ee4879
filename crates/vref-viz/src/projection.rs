//! How a view's 3D positions become points on its panel.

use std::fmt;
use std::str::FromStr;

use vref_scene::SceneGraph;

/// A flattening of camera-frame positions (x right, y down, z forward) to
/// two dimensions, with the second coordinate growing downwards on the page.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Projection {
    /// Chosen from the data: `Pixels` when every object of a view has the
    /// same z (image data sets such as CMU House), else `Perspective` when
    /// every object is in front of its camera, else `TopDown`.
    #[default]
    Auto,
    /// (x, y): the positions already are image coordinates.
    Pixels,
    /// (x/z, y/z): onto the camera's image plane, as the camera sees them.
    Perspective,
    /// (x, -z): seen from above, the camera at the bottom looking up.
    TopDown,
}

impl Projection {
    pub const NAMES: [&'static str; 4] = ["auto", "pixels", "perspective", "top-down"];

    pub fn name(self) -> &'static str {
        match self {
            Projection::Auto => "auto",
            Projection::Pixels => "pixels",
            Projection::Perspective => "perspective",
            Projection::TopDown => "top-down",
        }
    }

    /// The concrete projection for `views`, all drawn the same way so that
    /// they can be compared.
    pub fn resolve(self, views: &[&SceneGraph]) -> Projection {
        if self != Projection::Auto {
            return self;
        }
        let objects = || views.iter().flat_map(|v| v.objects());
        if views.iter().all(|v| flat(v)) {
            return Projection::Pixels;
        }
        let far = objects().map(|o| o.position.z.abs()).fold(0.0, f64::max);
        // Objects at or behind the camera plane have no image; nearly on it
        // they would fling everything else into one corner.
        if objects().all(|o| o.position.z > 1e-3 * far) {
            Projection::Perspective
        } else {
            Projection::TopDown
        }
    }

    /// Where `position` lands, second coordinate downwards. `Auto` must be
    /// resolved first; it is treated as `Pixels`.
    pub(crate) fn apply(self, position: [f64; 3]) -> (f64, f64) {
        let [x, y, z] = position;
        match self {
            Projection::Auto | Projection::Pixels => (x, y),
            Projection::Perspective => (x / z, y / z),
            Projection::TopDown => (x, -z),
        }
    }

    /// What a reader needs to know to read a panel drawn this way.
    pub(crate) fn caption(self) -> &'static str {
        match self {
            Projection::Auto | Projection::Pixels => "image coordinates",
            Projection::Perspective => "camera image plane (x/z, y/z)",
            Projection::TopDown => "seen from above: camera at the bottom, looking up",
        }
    }
}

/// Whether every object of `view` has the same z.
fn flat(view: &SceneGraph) -> bool {
    let mut zs = view.objects().iter().map(|o| o.position.z);
    match zs.next() {
        Some(first) => zs.all(|z| z == first),
        None => true,
    }
}

impl fmt::Display for Projection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A projection name that is none of [`Projection::NAMES`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown projection `{0}` (expected one of: auto, pixels, perspective, top-down)")]
pub struct UnknownProjection(pub String);

impl FromStr for Projection {
    type Err = UnknownProjection;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        [
            Projection::Auto,
            Projection::Pixels,
            Projection::Perspective,
            Projection::TopDown,
        ]
        .into_iter()
        .find(|p| p.name() == s)
        .ok_or_else(|| UnknownProjection(s.to_owned()))
    }
}

/// Maps projected points into a pixel rectangle, same scale on both axes
/// (distances in the picture are then comparable, as the matcher's are).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fit {
    scale: f64,
    offset: (f64, f64),
}

impl Fit {
    /// Fits the bounding box of `points` centred into `rect` (left, top,
    /// right, bottom). A single point or none lands in the middle.
    pub(crate) fn new(points: &[(f64, f64)], rect: (i32, i32, i32, i32)) -> Self {
        let (left, top, right, bottom) = rect;
        let (w, h) = (f64::from(right - left), f64::from(bottom - top));
        let mut min = (f64::INFINITY, f64::INFINITY);
        let mut max = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        for &(x, y) in points {
            min = (min.0.min(x), min.1.min(y));
            max = (max.0.max(x), max.1.max(y));
        }
        if points.is_empty() {
            (min, max) = ((0.0, 0.0), (0.0, 0.0));
        }
        let span = ((max.0 - min.0) / w.max(1.0)).max((max.1 - min.1) / h.max(1.0));
        let scale = if span > 0.0 && span.is_finite() {
            1.0 / span
        } else {
            1.0
        };
        let centre = ((min.0 + max.0) / 2.0, (min.1 + max.1) / 2.0);
        let middle = (f64::from(left) + w / 2.0, f64::from(top) + h / 2.0);
        Self {
            scale,
            offset: (middle.0 - centre.0 * scale, middle.1 - centre.1 * scale),
        }
    }

    pub(crate) fn pixel(&self, (x, y): (f64, f64)) -> (i32, i32) {
        // `as` saturates, so even an absurd point stays a valid pixel.
        (
            (x * self.scale + self.offset.0).round() as i32,
            (y * self.scale + self.offset.1).round() as i32,
        )
    }
}
