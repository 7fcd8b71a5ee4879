//! A folder of RGB-D frames as a feed (`rgbd:DIR`): every frame measured
//! at start-up, with its own masks where it has them and the segmenter's
//! otherwise, then shown in turn like a dataset's scenes, each for the
//! hold, chosen by the time since the epoch. The folder layout is
//! [`vref_perception::folder`]'s.
//!
//! A frame where the segmenter finds no supporting plane is published with
//! zero objects (and the reason logged and counted): the feed keeps
//! running, and a live camera's next frame may well have a table in view.

use std::path::Path;

use vref_perception::folder::{RgbdImages, frame_dirs};
use vref_perception::{
    Frame, FrontEnd, LabelImage, Mask, NoiseSource, PerceptionSettings, RgbdFrame, Segmentation,
    SegmentationSettings, Segmenter, label_masks,
};
use vref_scene::Side;

use crate::SetupError;
use crate::dataset::View;
use crate::entries::entry;

/// Track ids of frame `k` are its labels plus `k` times this, so that no
/// id names objects of two frames.
const FRAME_ID_STRIDE: u64 = 100_000;

/// What the start-up measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RgbdSummary {
    pub frames: usize,
    /// Frames that brought their own masks.
    pub with_masks: usize,
    /// Frames where the segmenter found no supporting plane.
    pub no_support: usize,
    pub objects: usize,
}

/// Every frame of `dir` as this side's views, in the folder's order.
pub(crate) fn load_views(
    dir: &Path,
    side: Side,
    perception: PerceptionSettings,
    segmentation: SegmentationSettings,
    noise: NoiseSource,
) -> Result<(Vec<View>, RgbdSummary), SetupError> {
    let folder = |source| SetupError::Rgbd {
        path: dir.to_owned(),
        source,
    };
    let frames = frame_dirs(dir).map_err(folder)?;
    let configured = match side {
        Side::Robot => perception.robot(),
        Side::Human => perception.human(),
    };
    let mut summary = RgbdSummary::default();
    let mut views = Vec::with_capacity(frames.len());
    let mut detections = Vec::new();
    let mut told = Vec::new();
    for (k, (name, path)) in frames.iter().enumerate() {
        let images = RgbdImages::load(path, perception.image_limit()).map_err(folder)?;
        // Said once for the frames that share a camera file.
        if k == 0 || images.unread_keys != told {
            crate::warn_unread(&images.unread_keys, name);
            told.clone_from(&images.unread_keys);
        }
        // Each frame's segmenter and stated errors are set for the noise
        // its camera shows (or is configured with).
        let mut settings = configured;
        settings.noise.pixel = crate::frame_law(noise, &images.depth, configured.noise.pixel, name);
        let mut front_end = FrontEnd::new(settings);
        let mut up = None;
        let labels = match images.masks {
            Some(ref masks) => {
                summary.with_masks += 1;
                masks.clone()
            }
            None => {
                let mut labels = LabelImage::new(1, 1);
                let mut segmenter = Segmenter::new(segmentation.for_camera(settings.noise.pixel));
                let frame = RgbdFrame {
                    colour: &images.colour,
                    depth: &images.depth,
                    intrinsics: images.camera.intrinsics,
                    up: None,
                };
                let segmentation = segmenter.segment(&frame, &mut labels).map_err(|source| {
                    SetupError::Segment {
                        path: path.clone(),
                        source,
                    }
                })?;
                match segmentation {
                    Segmentation::Objects { plane, .. } => {
                        // The plane the objects stand on is level: its
                        // normal is the view's up vector.
                        up = Some(plane.normal.map(|c| c as f32));
                    }
                    Segmentation::NoSupport(reason) => {
                        summary.no_support += 1;
                        tracing::warn!(frame = %name, "{reason}: published with 0 objects");
                    }
                }
                labels
            }
        };
        let label_masks = label_masks(&labels);
        let offset = FRAME_ID_STRIDE * k as u64;
        let masks: Vec<Mask<'_>> = label_masks
            .iter()
            .map(|m| Mask {
                id: offset + u64::from(m.label),
                pixels: &m.pixels,
            })
            .collect();
        let frame = Frame {
            colour: &images.colour,
            depth: &images.depth,
            intrinsics: images.camera.intrinsics,
            masks: &masks,
        };
        front_end
            .process(&frame, &mut detections)
            .map_err(|source| SetupError::Frame {
                path: path.clone(),
                source,
            })?;
        let entries = detections
            .iter()
            .map(|d| entry(d.id, d.position, d.sigma, &d.feature))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|source| SetupError::Entry {
                origin: path.display().to_string(),
                source,
            })?;
        tracing::debug!(frame = %name, objects = entries.len(), "measured");
        summary.objects += entries.len();
        views.push(View {
            feature_dim: vref_perception::FEATURE_DIM,
            entries,
            up,
        });
    }
    summary.frames = views.len();
    Ok((views, summary))
}
