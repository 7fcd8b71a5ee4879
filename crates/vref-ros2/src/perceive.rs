//! One paired frame to the objects of a robot snapshot: rectified where
//! its camera states a lens distortion, the user's label image where one
//! came, vref's segmenter otherwise, then the front end. Buffers are kept
//! from frame to frame.

use image::GrayImage;
use vref_feed::EntryError;
use vref_perception::{
    DepthImage, Detection, Distortion, FrameError, FrontEnd, FrontEndSettings, Intrinsics,
    LabelImage, LensError, Mask, NoiseSource, Rectifier, RgbdFrame, SegmentError, Segmentation,
    SegmentationSettings, Segmenter, pixel_noise,
};

use crate::decode::CameraModel;
use vref_wire::ObjectEntry;

/// Why a frame gave no snapshot.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PerceiveError {
    #[error("segmenting")]
    Segment(#[source] SegmentError),
    #[error("measuring the objects")]
    Frame(#[source] FrameError),
    #[error("an object for the wire")]
    Entry(#[source] EntryError),
    #[error("rectifying")]
    Lens(#[source] LensError),
    #[error("no object in the frame ({reason})")]
    NoObjects { reason: String },
    #[error("{found} objects, more than the scene's capacity of {capacity}")]
    TooMany { found: usize, capacity: usize },
    #[error("labels are {found_width}x{found_height}, the colour image {width}x{height}")]
    LabelSize {
        width: u32,
        height: u32,
        found_width: u32,
        found_height: u32,
    },
}

impl PerceiveError {
    pub fn reason(&self) -> &'static str {
        match self {
            PerceiveError::Segment(_) => "segment",
            PerceiveError::Frame(_) => "frame",
            PerceiveError::Entry(_) => "entry",
            PerceiveError::Lens(_) => "distortion",
            PerceiveError::NoObjects { .. } => "no_objects",
            PerceiveError::TooMany { .. } => "too_many_objects",
            PerceiveError::LabelSize { .. } => "label_size",
        }
    }
}

/// The segmenter, the front end and their buffers.
#[derive(Debug)]
pub struct Perception {
    segmenter: Segmenter,
    front_end: FrontEnd,
    /// `[segmentation]`, set for the reference camera: the segmenter's
    /// thresholds are these scaled for the camera's noise.
    segmentation: SegmentationSettings,
    /// Whether the camera's per-reading noise is still to be measured
    /// (`NoiseSource::Frame` until a frame shows enough depth).
    measuring: bool,
    capacity: usize,
    own_labels: LabelImage,
    ids: Vec<u16>,
    masks: Vec<GrayImage>,
    detections: Vec<Detection>,
    entries: Vec<ObjectEntry>,
    /// The last lens's rectification map, kept while frames come from it.
    rectifier: Option<(Intrinsics, Distortion, Rectifier)>,
}

/// One frame's objects for the wire, and which way is up in its camera
/// frame: the normal of the supporting plane vref's segmenter found (a
/// camera that sees a table sees the table's normal, as the rgbd: source
/// and `vref match` take it); `None` for a frame that came with its own
/// labels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Perceived<'a> {
    pub entries: &'a [ObjectEntry],
    pub up: Option<[f32; 3]>,
}

impl Perception {
    /// `capacity`: the most objects a snapshot may hold (`[scene]`);
    /// `noise`: where the camera's per-reading depth noise comes from
    /// (`[ros2] depth_noise`): measured on its first frame that shows
    /// enough depth, else `front_end`'s, which holds until then.
    pub fn new(
        front_end: FrontEndSettings,
        segmentation: SegmentationSettings,
        noise: NoiseSource,
        capacity: usize,
    ) -> Self {
        Self {
            segmenter: Segmenter::new(segmentation.for_camera(front_end.noise.pixel)),
            front_end: FrontEnd::new(front_end),
            segmentation,
            measuring: noise == NoiseSource::Frame,
            capacity,
            own_labels: LabelImage::new(1, 1),
            ids: Vec::new(),
            masks: Vec::new(),
            detections: Vec::new(),
            entries: Vec::new(),
            rectifier: None,
        }
    }

    /// The frame's objects as wire entries (track id = label value), or
    /// why there are none to publish: its images rectified first where
    /// `camera` states a lens (the labels too, which are of the raw image
    /// as well).
    pub fn process(
        &mut self,
        colour: &image::RgbImage,
        depth: &DepthImage,
        camera: &CameraModel,
        labels: Option<&LabelImage>,
    ) -> Result<Perceived<'_>, PerceiveError> {
        if let Some(l) = labels
            && l.dimensions() != colour.dimensions()
        {
            let (width, height) = colour.dimensions();
            let (found_width, found_height) = l.dimensions();
            return Err(PerceiveError::LabelSize {
                width,
                height,
                found_width,
                found_height,
            });
        }
        let Some(lens) = camera.lens else {
            return self.perceive(colour, depth, camera.intrinsics, labels);
        };
        let (width, height) = colour.dimensions();
        let kept = self
            .rectifier
            .take()
            .filter(|(k, l, r)| (*k, *l, r.size()) == (camera.intrinsics, lens, (width, height)));
        let (_, _, rectifier) = kept.unwrap_or_else(|| {
            let map = Rectifier::new(&camera.intrinsics, &lens, width, height);
            (camera.intrinsics, lens, map)
        });
        let rectified = rectifier
            .frame(colour, depth.pixels(), labels)
            .map_err(PerceiveError::Lens);
        self.rectifier = Some((camera.intrinsics, lens, rectifier));
        let (colour, depth_pixels, labels) = rectified?;
        let depth =
            DepthImage::new(depth_pixels, depth.metres_per_unit()).map_err(PerceiveError::Frame)?;
        self.perceive(&colour, &depth, camera.intrinsics, labels.as_ref())
    }

    /// [`Perception::process`] of a pinhole camera's frame, its labels
    /// (if any) of the colour image's size.
    fn perceive(
        &mut self,
        colour: &image::RgbImage,
        depth: &DepthImage,
        intrinsics: Intrinsics,
        labels: Option<&LabelImage>,
    ) -> Result<Perceived<'_>, PerceiveError> {
        if self.measuring {
            self.measure_noise(depth);
        }
        let mut up = None;
        let labels = match labels {
            Some(l) => l,
            None => {
                let frame = RgbdFrame {
                    colour,
                    depth,
                    intrinsics,
                    up: None,
                };
                let result = self
                    .segmenter
                    .segment(&frame, &mut self.own_labels)
                    .map_err(PerceiveError::Segment)?;
                match result {
                    Segmentation::NoSupport(why) => {
                        return Err(PerceiveError::NoObjects {
                            reason: why.to_string(),
                        });
                    }
                    Segmentation::Objects { plane, .. } => {
                        up = Some(plane.normal.map(|c| c as f32));
                    }
                }
                &self.own_labels
            }
        };
        split_labels(labels, &mut self.ids, &mut self.masks);
        if self.ids.len() > self.capacity {
            return Err(PerceiveError::TooMany {
                found: self.ids.len(),
                capacity: self.capacity,
            });
        }
        let masks: Vec<Mask<'_>> = self
            .ids
            .iter()
            .zip(&self.masks)
            .map(|(&id, pixels)| Mask {
                id: u64::from(id),
                pixels,
            })
            .collect();
        let frame = vref_perception::Frame {
            colour,
            depth,
            intrinsics,
            masks: &masks,
        };
        let skipped = self
            .front_end
            .process(&frame, &mut self.detections)
            .map_err(PerceiveError::Frame)?;
        self.entries.clear();
        for d in &self.detections {
            self.entries.push(
                vref_feed::entries::entry(d.id, d.position, d.sigma, &d.feature)
                    .map_err(PerceiveError::Entry)?,
            );
        }
        if self.entries.is_empty() {
            return Err(PerceiveError::NoObjects {
                reason: format!(
                    "{} labels, {} too small, {} without depth",
                    self.ids.len(),
                    skipped.too_small,
                    skipped.no_depth
                ),
            });
        }
        Ok(Perceived {
            entries: &self.entries,
            up,
        })
    }
}

impl Perception {
    /// Sets the segmenter and the front end for the noise `depth` shows;
    /// a camera's noise is its own, so once measured it is kept (a live
    /// stream is not measured frame by frame).
    fn measure_noise(&mut self, depth: &DepthImage) {
        let Some(measured) = pixel_noise(depth) else {
            return;
        };
        tracing::info!(
            c = measured.c,
            samples = measured.samples,
            "depth noise measured on the camera's first frame: sigma = c z^2"
        );
        let law = measured.law();
        let mut settings = *self.front_end.settings();
        settings.noise.pixel = law;
        self.front_end = FrontEnd::new(settings);
        self.segmenter = Segmenter::new(self.segmentation.for_camera(law));
        self.measuring = false;
    }

    /// The per-reading law the camera's frames are measured with now.
    pub fn pixel_law(&self) -> vref_perception::DepthLaw {
        self.front_end.settings().noise.pixel
    }
}

/// The distinct non-zero labels (ascending) and one mask per label; the
/// mask buffers are reused.
fn split_labels(labels: &LabelImage, ids: &mut Vec<u16>, masks: &mut Vec<GrayImage>) {
    let mut seen = vec![false; usize::from(u16::MAX) + 1];
    for &l in labels.as_raw() {
        seen[usize::from(l)] = true;
    }
    ids.clear();
    ids.extend((1..=u16::MAX).filter(|&l| seen[usize::from(l)]));
    let (w, h) = labels.dimensions();
    masks.truncate(ids.len());
    for m in masks.iter_mut() {
        if m.dimensions() == (w, h) {
            m.fill(0);
        } else {
            *m = GrayImage::new(w, h);
        }
    }
    while masks.len() < ids.len() {
        masks.push(GrayImage::new(w, h));
    }
    let mut slot = vec![usize::MAX; usize::from(u16::MAX) + 1];
    for (i, &id) in ids.iter().enumerate() {
        slot[usize::from(id)] = i;
    }
    for (p, &l) in labels.as_raw().iter().enumerate() {
        if l != 0
            && let Some(m) = masks.get_mut(slot[usize::from(l)])
            && let Some(px) = m.get_mut(p)
        {
            *px = 255;
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;
    use image::Luma;

    #[test]
    fn labels_split_into_one_mask_each() {
        let mut labels = LabelImage::new(3, 2);
        labels.put_pixel(0, 0, Luma([5]));
        labels.put_pixel(2, 1, Luma([9]));
        labels.put_pixel(1, 1, Luma([5]));
        let (mut ids, mut masks) = (Vec::new(), Vec::new());
        split_labels(&labels, &mut ids, &mut masks);
        assert_eq!(ids, vec![5, 9]);
        assert_eq!(masks[0].as_raw(), &vec![255, 0, 0, 0, 255, 0]);
        assert_eq!(masks[1].as_raw(), &vec![0, 0, 0, 0, 0, 255]);
        // Reused for a frame with fewer objects.
        labels.put_pixel(2, 1, Luma([0]));
        split_labels(&labels, &mut ids, &mut masks);
        assert_eq!((ids.len(), masks.len()), (1, 1));
    }

    /// A table 0.6 m below a camera looking down at it, with a box 6 cm
    /// tall on it (its top only: the sides are depth jumps), all grey.
    fn table_with_a_box(up: [f64; 3]) -> (image::RgbImage, DepthImage, LabelImage) {
        table_with_a_box_at(up, 280..360, 260..330)
    }

    /// [`table_with_a_box`] with the box's top seen at pixels `us` x `vs`.
    fn table_with_a_box_at(
        up: [f64; 3],
        us: std::ops::Range<u32>,
        vs: std::ops::Range<u32>,
    ) -> (image::RgbImage, DepthImage, LabelImage) {
        let (w, h, f) = (640u32, 480u32, 525.0);
        let mut depth = vref_perception::DepthPixels::new(w, h);
        let mut labels = LabelImage::new(w, h);
        for v in 0..h {
            for u in 0..w {
                let ray = [(f64::from(u) - 319.5) / f, (f64::from(v) - 239.5) / f, 1.0];
                let along: f64 = ray.iter().zip(&up).map(|(a, b)| a * b).sum();
                let on_box = us.contains(&u) && vs.contains(&v);
                let below = if on_box { 0.6 - 0.06 } else { 0.6 };
                let z = -below / along;
                depth.put_pixel(u, v, Luma([(z * 1000.0).round() as u16]));
                if on_box {
                    labels.put_pixel(u, v, Luma([7]));
                }
            }
        }
        let colour = image::RgbImage::from_pixel(w, h, image::Rgb([150, 150, 150]));
        (colour, DepthImage::new(depth, 0.001).unwrap(), labels)
    }

    /// The camera of [`table_with_a_box`]'s frames.
    fn pinhole() -> CameraModel {
        CameraModel {
            intrinsics: Intrinsics::new(525.0, 525.0, 319.5, 239.5).unwrap(),
            lens: None,
            width: 640,
            height: 480,
        }
    }

    /// `image` of the pinhole camera as a camera of the same intrinsics
    /// with `lens` records it: each raw pixel takes the pinhole pixel its
    /// ray passes through.
    fn recorded<P: image::Pixel>(
        image: &image::ImageBuffer<P, Vec<P::Subpixel>>,
        lens: &Distortion,
        empty: P,
    ) -> image::ImageBuffer<P, Vec<P::Subpixel>> {
        let k = pinhole().intrinsics;
        let (w, h) = image.dimensions();
        image::ImageBuffer::from_fn(w, h, |u, v| {
            let (x, y) = lens.undistort(
                (f64::from(u) - k.cx()) / k.fx(),
                (f64::from(v) - k.cy()) / k.fy(),
            );
            let (pu, pv) = ((k.fx() * x + k.cx()).round(), (k.fy() * y + k.cy()).round());
            if (0.0..f64::from(w)).contains(&pu) && (0.0..f64::from(h)).contains(&pv) {
                *image.get_pixel(pu as u32, pv as u32)
            } else {
                empty
            }
        })
    }

    /// A raw frame of a camera whose lens bends rays is rectified before
    /// anything else when its CameraInfo states the lens: a box near the
    /// image's corner comes out where the pinhole camera puts it, and a
    /// centimetre off when the lens is not stated (the lens shrinks rays
    /// there by about 3.7 %, and the box is 0.33 m off the axis).
    #[test]
    fn a_raw_frame_is_rectified_before_it_is_perceived() {
        let (colour, depth, labels) = table_with_a_box_at([0.0, -0.6, -0.8], 540..600, 400..450);
        let lens = Distortion::PlumbBob([-0.12, 0.05, 0.0, 0.0, 0.0]);
        let raw_depth = recorded(depth.pixels(), &lens, Luma([0]));
        let raw_depth = DepthImage::new(raw_depth, depth.metres_per_unit()).unwrap();
        let raw_colour = recorded(&colour, &lens, image::Rgb([0, 0, 0]));
        let raw_labels = recorded(&labels, &lens, Luma([0]));
        let mut perception = Perception::new(
            vref_perception::PerceptionSettings::default().robot(),
            SegmentationSettings::default(),
            NoiseSource::Config,
            64,
        );
        let mut place = |colour, depth, camera: CameraModel, labels| {
            let found = perception
                .process(colour, depth, &camera, Some(labels))
                .unwrap();
            assert_eq!(found.entries.len(), 1);
            found.entries[0].position.map(f64::from)
        };
        let truth = place(&colour, &depth, pinhole(), &labels);
        let with_lens = CameraModel {
            lens: Some(lens),
            ..pinhole()
        };
        let rectified = place(&raw_colour, &raw_depth, with_lens, &raw_labels);
        let unrectified = place(&raw_colour, &raw_depth, pinhole(), &raw_labels);
        let off = |p: [f64; 3]| -> f64 {
            p.iter()
                .zip(truth)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        assert!(off(rectified) < 0.005, "{rectified:?} against {truth:?}");
        assert!(
            off(unrectified) > 0.008,
            "{unrectified:?} against {truth:?}"
        );
        // Labels of another size are that, not a rectification's failure.
        let small = LabelImage::new(4, 4);
        let err = perception
            .process(&raw_colour, &raw_depth, &with_lens, Some(&small))
            .unwrap_err();
        assert_eq!(err.reason(), "label_size");
    }

    /// Where vref segmented the frame, the supporting plane's normal is
    /// the frame's up vector; a frame with its own labels has none.
    #[test]
    fn a_segmented_frame_carries_its_tables_normal_as_up() {
        let norm = (1.0f64 + 0.64).sqrt();
        let up = [0.0, -1.0 / norm, -0.8 / norm];
        let (colour, depth, labels) = table_with_a_box(up);
        let camera = pinhole();
        let mut perception = Perception::new(
            vref_perception::PerceptionSettings::default().robot(),
            SegmentationSettings::default(),
            NoiseSource::Config,
            64,
        );
        let found = perception.process(&colour, &depth, &camera, None).unwrap();
        assert_eq!(found.entries.len(), 1);
        let got = found.up.unwrap().map(f64::from);
        let cos: f64 = got.iter().zip(&up).map(|(a, b)| a * b).sum();
        assert!(cos > 0.9995, "up {got:?} against {up:?}");
        let given = perception
            .process(&colour, &depth, &camera, Some(&labels))
            .unwrap();
        assert_eq!(given.entries.len(), 1);
        assert_eq!(given.up, None);
    }

    /// With `[ros2] depth_noise = "frame"` a camera's noise is measured on
    /// its first frame that shows depth and kept: the headset's configured
    /// law (0.02 z^2) gives way to what the frame shows; a frame without
    /// depth changes nothing; "config" keeps the configured law.
    #[test]
    fn the_cameras_noise_is_measured_on_its_first_frame_with_depth() {
        let (colour, depth, _) = table_with_a_box([0.0, -1.0, 0.0]);
        let camera = pinhole();
        let (w, h) = colour.dimensions();
        let bare = DepthImage::new(vref_perception::DepthPixels::new(w, h), 0.001).unwrap();
        let headset = vref_perception::PerceptionSettings::default().human();
        let configured = headset.noise.pixel;
        let perception =
            |noise| Perception::new(headset, SegmentationSettings::default(), noise, 64);
        let mut measuring = perception(NoiseSource::Frame);
        assert!(measuring.process(&colour, &bare, &camera, None).is_err());
        assert_eq!(measuring.pixel_law(), configured);
        measuring.process(&colour, &depth, &camera, None).unwrap();
        let measured = measuring.pixel_law();
        assert!(
            measured.c > 0.0 && measured.c < configured.c / 4.0,
            "{measured:?}"
        );
        let _ = measuring.process(&colour, &bare, &camera, None);
        assert_eq!(measuring.pixel_law(), measured);
        let mut configured_only = perception(NoiseSource::Config);
        // Set for the rendered headset, the segmenter may well find
        // nothing here; what matters is the law it kept.
        let _ = configured_only.process(&colour, &depth, &camera, None);
        assert_eq!(configured_only.pixel_law(), configured);
    }
}
