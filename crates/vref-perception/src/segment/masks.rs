//! A label image as the front end's masks: one 8-bit mask per label.

use image::GrayImage;

use super::LabelImage;

/// One mask per label present in `labels` (0 is background), in label
/// order, with the label and its pixel count.
pub fn label_masks(labels: &LabelImage) -> Vec<LabelMask> {
    let (w, h) = labels.dimensions();
    let mut slot: Vec<Option<usize>> = Vec::new();
    let mut masks: Vec<LabelMask> = Vec::new();
    for (u, v, pixel) in labels.enumerate_pixels() {
        let label = pixel.0[0];
        if label == 0 {
            continue;
        }
        let k = usize::from(label);
        if slot.len() <= k {
            slot.resize(k + 1, None);
        }
        let index = *slot[k].get_or_insert_with(|| {
            masks.push(LabelMask {
                label,
                pixels: GrayImage::new(w, h),
                area: 0,
                sum_u: 0,
                sum_v: 0,
            });
            masks.len() - 1
        });
        let mask = &mut masks[index];
        mask.pixels.put_pixel(u, v, image::Luma([255]));
        mask.area += 1;
        mask.sum_u += u64::from(u);
        mask.sum_v += u64::from(v);
    }
    masks.sort_by_key(|m| m.label);
    masks
}

/// One label's pixels.
#[derive(Debug, Clone)]
pub struct LabelMask {
    pub label: u16,
    /// 255 on the label's pixels, 0 elsewhere.
    pub pixels: GrayImage,
    pub area: u64,
    sum_u: u64,
    sum_v: u64,
}

impl LabelMask {
    /// The mean pixel (u, v) of the label.
    pub fn centroid(&self) -> [f64; 2] {
        let n = self.area.max(1) as f64;
        [self.sum_u as f64 / n, self.sum_v as f64 / n]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_mask_per_label_in_label_order() {
        let labels = LabelImage::from_fn(4, 2, |u, _| image::Luma([[0, 7, 7, 2][u as usize]]));
        let masks = label_masks(&labels);
        assert_eq!(masks.iter().map(|m| m.label).collect::<Vec<_>>(), [2, 7]);
        assert_eq!(masks[1].area, 4);
        assert_eq!(masks[1].centroid(), [1.5, 0.5]);
        assert_eq!(masks[0].pixels.get_pixel(3, 1).0[0], 255);
        assert_eq!(masks[0].pixels.get_pixel(1, 1).0[0], 0);
    }
}
