//! A BOP dataset's images as the feeds show them (`--source bop:DIR`):
//! the scenes in the feeds' order, with the track ids the feeds publish,
//! taken from the same [`BopWorld`] the feeds build.

use std::path::{Path, PathBuf};

use vref_feed::{BopImageSource, BopSceneSource, BopWorld};
use vref_import::{BopSceneDir, ImportError};
use vref_perception::{ImageLimit, LoadError, image_size, load_mask, outline_polygons};

use crate::images::{CameraImage, ImageObject, Images, SceneImages};

/// Why a scene's images could not be loaded for viewing.
#[derive(Debug, thiserror::Error)]
pub enum ImagesError {
    #[error("reading {path}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: not a JPEG or PNG image (by its extension)")]
    Format { path: PathBuf },
    #[error(transparent)]
    Camera(#[from] ImportError),
    #[error(transparent)]
    Mask(#[from] LoadError),
}

/// Every scene's two images, their intrinsics and each published object's
/// mask outline. `world` must be the feeds' (same folder, same
/// `[perception]` and `[scene]` settings), or the track ids will not be
/// the ones they publish.
/// Every image larger than `limit` is refused before it is read.
pub fn load_bop_images(world: &BopWorld, limit: ImageLimit) -> Result<Images, ImagesError> {
    let scenes = world
        .sources()
        .iter()
        .map(|source: &BopSceneSource| {
            Ok(SceneImages {
                name: source.name.clone(),
                robot: camera(&source.scene, &source.robot, limit)?,
                human: camera(&source.scene, &source.human, limit)?,
            })
        })
        .collect::<Result<_, ImagesError>>()?;
    Ok(Images::new(scenes))
}

fn camera(
    scene: &BopSceneDir,
    view: &BopImageSource,
    limit: ImageLimit,
) -> Result<CameraImage, ImagesError> {
    let path = scene.colour_path(view.image);
    let format = format_of(&path).ok_or_else(|| ImagesError::Format { path: path.clone() })?;
    // The size from the header, checked before the file is read whole.
    let (width, height) = image_size(&path)?;
    limit.check(&path, (width, height))?;
    let data = std::fs::read(&path).map_err(|source| ImagesError::Read {
        path: path.clone(),
        source,
    })?;
    let i = scene.intrinsics(view.image)?;
    let mut objects = Vec::new();
    for (k, id) in view.track_ids.iter().enumerate() {
        if let Some(track_id) = id {
            let mask = load_mask(&scene.mask_path(view.image, k), limit)?;
            objects.push(ImageObject {
                track_id: *track_id,
                polygons: outline_polygons(&mask),
            });
        }
    }
    objects.sort_by_key(|o| o.track_id);
    Ok(CameraImage {
        format,
        data,
        width,
        height,
        k: [i.fx(), 0.0, i.cx(), 0.0, i.fy(), i.cy(), 0.0, 0.0, 1.0],
        objects,
    })
}

/// Foxglove's name of the image's format.
fn format_of(path: &Path) -> Option<&'static str> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    match ext.as_str() {
        "jpg" | "jpeg" => Some("jpeg"),
        "png" => Some("png"),
        _ => None,
    }
}
