//! The BOP dataset layout (https://bop.felk.cvut.cz/datasets/): a dataset
//! folder holds `SPLIT/SCENE/` folders, each with `scene_camera.json`
//! (per image: `cam_K`, `depth_scale`), `scene_gt.json` (per image: the
//! instances in one order, each `obj_id`, `cam_R_m2c`, `cam_t_m2c` in
//! millimetres), `rgb/IM.jpg` (or `.png`), `depth/IM.png` (16-bit,
//! millimetres times `depth_scale`) and `mask_visib/IM_GT.png`.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use image::{GrayImage, RgbImage};
use serde::Deserialize;
use vref_perception::{DepthImage, ImageLimit, Intrinsics, load_colour, load_depth, load_mask};

use crate::ImportError;

/// One dataset folder and its scenes of one split.
#[derive(Debug, Clone)]
pub struct BopDataset {
    name: String,
    scenes: Vec<BopSceneDir>,
}

/// One scene folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BopSceneDir {
    pub id: u32,
    pub dir: PathBuf,
}

/// One image of a scene, decoded and checked.
#[derive(Debug, Clone)]
pub struct BopView {
    pub colour: RgbImage,
    pub depth: DepthImage,
    pub intrinsics: Intrinsics,
    /// One mask per ground-truth instance, in `scene_gt.json`'s order.
    pub masks: Vec<GrayImage>,
    /// Each instance's `cam_t_m2c`, metres: the object model's origin in
    /// the camera frame.
    pub origins: Vec<[f64; 3]>,
    /// Each instance's `obj_id`.
    pub object_ids: Vec<u32>,
    /// `cam_R_w2c`: the world-to-camera rotation, row-major, where the
    /// dataset gives it.
    pub world_to_camera: Option<[f64; 9]>,
}

#[derive(Deserialize)]
struct CameraRecord {
    #[serde(rename = "cam_K")]
    cam_k: [f64; 9],
    #[serde(default = "unit_scale")]
    depth_scale: f64,
    /// World to camera rotation, row-major; absent in some datasets.
    #[serde(rename = "cam_R_w2c", default)]
    cam_r_w2c: Option<[f64; 9]>,
}

fn unit_scale() -> f64 {
    1.0
}

#[derive(Deserialize)]
struct GtRecord {
    obj_id: u32,
    cam_t_m2c: [f64; 3],
}

impl BopDataset {
    /// The scenes of `dir/split`, in order of their ids; the dataset is
    /// named after its folder.
    pub fn open(dir: &Path, split: &str) -> Result<Self, ImportError> {
        let split_dir = dir.join(split);
        let entries = fs::read_dir(&split_dir).map_err(|source| ImportError::Io {
            path: split_dir.clone(),
            source,
        })?;
        let mut scenes = Vec::new();
        for entry in entries {
            let entry = entry.map_err(|source| ImportError::Io {
                path: split_dir.clone(),
                source,
            })?;
            let path = entry.path();
            let id = path
                .file_name()
                .and_then(|n| n.to_str())
                .and_then(|n| n.parse::<u32>().ok());
            if let (Some(id), true) = (id, path.is_dir()) {
                scenes.push(BopSceneDir { id, dir: path });
            }
        }
        if scenes.is_empty() {
            return Err(ImportError::NoScenes { dir: split_dir });
        }
        scenes.sort_by_key(|s| s.id);
        let name = dir
            .canonicalize()
            .ok()
            .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_else(|| "bop".to_owned());
        Ok(Self { name, scenes })
    }

    /// The dataset folder's name (`table`, `floor`, `tless`, ...).
    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn scenes(&self) -> &[BopSceneDir] {
        &self.scenes
    }

    /// A scene's name: the dataset folder and the scene id, `table/000003`.
    pub fn scene_name(&self, scene: &BopSceneDir) -> String {
        format!("{}/{:06}", self.name, scene.id)
    }
}

/// The dataset folders under `dir`: `dir` itself when it holds `split`,
/// else each sub-folder that does, in name order.
pub fn datasets_in(dir: &Path, split: &str) -> Result<Vec<PathBuf>, ImportError> {
    if dir.join(split).is_dir() {
        return Ok(vec![dir.to_owned()]);
    }
    let entries = fs::read_dir(dir).map_err(|source| ImportError::Io {
        path: dir.to_owned(),
        source,
    })?;
    let mut found: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.join(split).is_dir())
        .collect();
    found.sort();
    if found.is_empty() {
        return Err(ImportError::NoScenes {
            dir: dir.join(split),
        });
    }
    Ok(found)
}

impl BopSceneDir {
    /// Image `image` of the scene: its camera, ground truth, colour, depth
    /// and every instance's mask, each checked to have the colour image's
    /// size.
    /// Every image larger than `limit` is refused before it is decoded.
    pub fn load_view(&self, image: u32, limit: ImageLimit) -> Result<BopView, ImportError> {
        let key = image.to_string();
        let (camera_path, camera) = self.camera_record(image)?;
        let intrinsics =
            Intrinsics::from_matrix(&camera.cam_k).map_err(|source| ImportError::Frame {
                path: camera_path.clone(),
                image,
                source,
            })?;
        let gt_path = self.dir.join("scene_gt.json");
        let gts: BTreeMap<String, Vec<GtRecord>> = read_json(&gt_path)?;
        let instances = gts.get(&key).ok_or_else(|| ImportError::MissingImage {
            path: gt_path.clone(),
            image,
        })?;

        let colour_path = self.colour_path(image);
        let colour = load_colour(&colour_path, limit).map_err(ImportError::from)?;
        let size = colour.dimensions();
        let depth_path = self.dir.join("depth").join(format!("{image:06}.png"));
        let depth_pixels = load_depth(&depth_path, limit)?;
        check_size(&depth_path, depth_pixels.dimensions(), &colour_path, size)?;
        let depth =
            DepthImage::new(depth_pixels, camera.depth_scale / 1000.0).map_err(|source| {
                ImportError::Frame {
                    path: camera_path.clone(),
                    image,
                    source,
                }
            })?;
        let mut masks = Vec::with_capacity(instances.len());
        for k in 0..instances.len() {
            let path = self.mask_path(image, k);
            let mask = load_mask(&path, limit)?;
            check_size(&path, mask.dimensions(), &colour_path, size)?;
            masks.push(mask);
        }
        Ok(BopView {
            colour,
            depth,
            intrinsics,
            masks,
            origins: instances
                .iter()
                .map(|g| g.cam_t_m2c.map(|v| v / 1000.0))
                .collect(),
            object_ids: instances.iter().map(|g| g.obj_id).collect(),
            world_to_camera: camera.cam_r_w2c,
        })
    }

    /// Image `image`'s camera record and the file it is in.
    fn camera_record(&self, image: u32) -> Result<(PathBuf, CameraRecord), ImportError> {
        let camera_path = self.dir.join("scene_camera.json");
        let mut cameras: BTreeMap<String, CameraRecord> = read_json(&camera_path)?;
        match cameras.remove(&image.to_string()) {
            Some(camera) => Ok((camera_path, camera)),
            None => Err(ImportError::MissingImage {
                path: camera_path,
                image,
            }),
        }
    }

    /// Image `image`'s camera (`cam_K` of `scene_camera.json`), checked.
    pub fn intrinsics(&self, image: u32) -> Result<Intrinsics, ImportError> {
        let (path, camera) = self.camera_record(image)?;
        Intrinsics::from_matrix(&camera.cam_k).map_err(|source| ImportError::Frame {
            path,
            image,
            source,
        })
    }

    /// The visible mask of instance `k` (in `scene_gt.json`'s order) in
    /// image `image`.
    pub fn mask_path(&self, image: u32, k: usize) -> PathBuf {
        self.dir
            .join("mask_visib")
            .join(format!("{image:06}_{k:06}.png"))
    }

    /// `rgb/IM.jpg`, else `rgb/IM.png` where only that exists (BOP
    /// datasets use both).
    pub fn colour_path(&self, image: u32) -> PathBuf {
        let jpg = self.dir.join("rgb").join(format!("{image:06}.jpg"));
        let png = jpg.with_extension("png");
        if !jpg.exists() && png.exists() {
            png
        } else {
            jpg
        }
    }
}

fn check_size(
    path: &Path,
    found: (u32, u32),
    reference: &Path,
    expected: (u32, u32),
) -> Result<(), ImportError> {
    if found == expected {
        return Ok(());
    }
    Err(ImportError::ImageSize {
        path: path.to_owned(),
        found,
        reference: reference.to_owned(),
        expected,
    })
}

fn read_json<T: for<'de> Deserialize<'de>>(path: &Path) -> Result<T, ImportError> {
    let text = fs::read_to_string(path).map_err(|source| ImportError::Io {
        path: path.to_owned(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|source| ImportError::Json {
        path: path.to_owned(),
        source,
    })
}
