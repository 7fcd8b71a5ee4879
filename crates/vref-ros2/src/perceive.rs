//! One paired frame to the objects of a robot snapshot: the user's label
//! image where one came, vref's segmenter otherwise, then the front end.
//! Buffers are kept from frame to frame.

use image::GrayImage;
use vref_feed::EntryError;
use vref_perception::{
    DepthImage, Detection, FrameError, FrontEnd, FrontEndSettings, Intrinsics, LabelImage, Mask,
    RgbdFrame, SegmentError, Segmentation, SegmentationSettings, Segmenter,
};
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
    capacity: usize,
    own_labels: LabelImage,
    ids: Vec<u16>,
    masks: Vec<GrayImage>,
    detections: Vec<Detection>,
    entries: Vec<ObjectEntry>,
}

impl Perception {
    /// `capacity`: the most objects a snapshot may hold (`[scene]`).
    pub fn new(
        front_end: FrontEndSettings,
        segmentation: SegmentationSettings,
        capacity: usize,
    ) -> Self {
        Self {
            segmenter: Segmenter::new(segmentation),
            front_end: FrontEnd::new(front_end),
            capacity,
            own_labels: LabelImage::new(1, 1),
            ids: Vec::new(),
            masks: Vec::new(),
            detections: Vec::new(),
            entries: Vec::new(),
        }
    }

    /// The frame's objects as wire entries (track id = label value), or
    /// why there are none to publish.
    pub fn process(
        &mut self,
        colour: &image::RgbImage,
        depth: &DepthImage,
        intrinsics: Intrinsics,
        labels: Option<&LabelImage>,
    ) -> Result<&[ObjectEntry], PerceiveError> {
        let labels = match labels {
            Some(l) => {
                if l.dimensions() != colour.dimensions() {
                    let (width, height) = colour.dimensions();
                    let (found_width, found_height) = l.dimensions();
                    return Err(PerceiveError::LabelSize {
                        width,
                        height,
                        found_width,
                        found_height,
                    });
                }
                l
            }
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
                if let Segmentation::NoSupport(why) = result {
                    return Err(PerceiveError::NoObjects {
                        reason: why.to_string(),
                    });
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
        Ok(&self.entries)
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
}
