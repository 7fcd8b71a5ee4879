//! The CMU House sequence as distributed by Caetano et al. (FGM layout):
//! `label/houseK` (30 lines "x y" in pixels), `adj/houseNNN.adj` (30 x 30
//! Delaunay adjacency), `scf/houseNNN.scf` (30 shape-context histograms).
//! Landmark `l` of every frame is the same physical point.

use std::fs;
use std::path::{Path, PathBuf};

use rand::SeedableRng;
use rand::seq::{SliceRandom, index};
use rand_chacha::ChaCha8Rng;
use vref_scene::{Limits, SceneGraph, SceneObject, ScenePair, Side};

use crate::ImportError;

/// How scene pairs are cut from the sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CmuHouseOptions {
    /// Frame gap: the human view is frame k, the robot view frame k + gap.
    pub gap: usize,
    /// Restrict each graph to its frame's Delaunay edges.
    pub delaunay: bool,
    /// Attach the shape contexts as appearance features.
    pub features: bool,
    /// Keep this many landmarks per frame, chosen at random independently
    /// in each view, so that both views have objects without partner.
    pub keep: Option<usize>,
    /// Seed of the landmark choice and of the robot-view object order.
    pub seed: u64,
}

#[derive(Debug, Clone)]
struct Frame {
    points: Vec<[f64; 2]>,
    adjacency: Vec<Vec<bool>>,
    features: Vec<Vec<f32>>,
}

/// The loaded sequence.
#[derive(Debug, Clone)]
pub struct CmuHouse {
    frames: Vec<Frame>,
}

impl CmuHouse {
    /// Loads every frame `label/house1`, `label/house2`, ... of `dir`.
    pub fn load(dir: &Path) -> Result<Self, ImportError> {
        let mut frames = Vec::new();
        for k in 1.. {
            let label = dir.join("label").join(format!("house{k}"));
            if !label.exists() {
                break;
            }
            frames.push(load_frame(dir, k, &label)?);
        }
        if frames.is_empty() {
            return Err(ImportError::NoFrames {
                dir: dir.to_owned(),
            });
        }
        Ok(Self { frames })
    }

    pub fn frames(&self) -> usize {
        self.frames.len()
    }

    /// Every pair (frame k, frame k + gap) in order of k.
    pub fn pairs(&self, options: &CmuHouseOptions) -> Result<Vec<ScenePair>, ImportError> {
        let count = self.frames.len();
        if options.gap >= count {
            return Err(ImportError::GapTooLarge {
                gap: options.gap,
                frames: count,
            });
        }
        let landmarks = self.frames[0].points.len();
        if let Some(keep) = options.keep
            && (keep == 0 || keep > landmarks)
        {
            return Err(ImportError::BadKeep { keep, landmarks });
        }
        let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
        (0..count - options.gap)
            .map(|k| self.pair(k, k + options.gap, options, &mut rng))
            .collect()
    }

    fn pair(
        &self,
        h: usize,
        r: usize,
        options: &CmuHouseOptions,
        rng: &mut ChaCha8Rng,
    ) -> Result<ScenePair, ImportError> {
        let name = format!("house{}-house{}", h + 1, r + 1);
        let landmarks = self.frames[h].points.len();
        let keep = options.keep.unwrap_or(landmarks);
        let human_kept = sorted_sample(rng, landmarks, keep);
        let mut robot_kept = sorted_sample(rng, landmarks, keep);
        // The robot view lists its objects in a random order, as a tracker
        // would: with both views in landmark order, any tie broken by
        // position in the matrix would look like a correct match.
        robot_kept.shuffle(rng);
        let ground_truth = human_kept
            .iter()
            .filter(|l| robot_kept.contains(l))
            .map(|&l| (l as u64, l as u64))
            .collect();
        let invalid = |side| {
            let name = name.clone();
            move |source| ImportError::Invalid {
                name,
                source: vref_scene::PairError::Graph { side, source },
            }
        };
        let human = self
            .graph(h, &human_kept, options)
            .map_err(invalid(Side::Human))?;
        let robot = self
            .graph(r, &robot_kept, options)
            .map_err(invalid(Side::Robot))?;
        ScenePair::new(name.clone(), robot, human, ground_truth)
            .map_err(|source| ImportError::Invalid { name, source })
    }

    fn graph(
        &self,
        k: usize,
        kept: &[usize],
        options: &CmuHouseOptions,
    ) -> Result<SceneGraph, vref_scene::GraphError> {
        let frame = &self.frames[k];
        let objects = kept
            .iter()
            .map(|&l| {
                let [x, y] = frame.points[l];
                let feature = if options.features {
                    frame.features[l].clone()
                } else {
                    Vec::new()
                };
                SceneObject::new(l as u64, [x, y, 0.0], feature)
            })
            .collect();
        let edges = options.delaunay.then(|| {
            let mut edges = Vec::new();
            for (p, &a) in kept.iter().enumerate() {
                for &b in &kept[p + 1..] {
                    if frame.adjacency[a][b] || frame.adjacency[b][a] {
                        edges.push([a as u64, b as u64]);
                    }
                }
            }
            edges
        });
        SceneGraph::new(objects, edges, &Limits::default())
    }
}

fn sorted_sample(rng: &mut ChaCha8Rng, len: usize, keep: usize) -> Vec<usize> {
    if keep == len {
        return (0..len).collect();
    }
    let mut chosen = index::sample(rng, len, keep).into_vec();
    chosen.sort_unstable();
    chosen
}

fn load_frame(dir: &Path, k: usize, label: &Path) -> Result<Frame, ImportError> {
    let points: Vec<[f64; 2]> = read_table(label, fixed::<2>)?;
    let n = points.len();
    let adj_path = dir.join("adj").join(format!("house{k:03}.adj"));
    let adjacency = read_table(&adj_path, |row, path, line| {
        if row.len() != n {
            return Err(shape(path, format!("{n} values on line {line}"), row.len()));
        }
        Ok(row.iter().map(|&v| v != 0.0).collect::<Vec<bool>>())
    })?;
    let scf_path = dir.join("scf").join(format!("house{k:03}.scf"));
    let features = read_table(&scf_path, |row, _, _| {
        Ok(row.iter().map(|&v| v as f32).collect::<Vec<f32>>())
    })?;
    for (path, rows) in [(&adj_path, adjacency.len()), (&scf_path, features.len())] {
        if rows != n {
            return Err(shape(
                path,
                format!("{n} rows like {}", label.display()),
                rows,
            ));
        }
    }
    Ok(Frame {
        points,
        adjacency,
        features,
    })
}

fn shape(path: &Path, expected: String, found: impl ToString) -> ImportError {
    ImportError::Shape {
        path: path.to_owned(),
        expected,
        found: found.to_string(),
    }
}

fn fixed<const N: usize>(row: &[f64], path: &Path, line: usize) -> Result<[f64; N], ImportError> {
    row.try_into()
        .map_err(|_| shape(path, format!("{N} values on line {line}"), row.len()))
}

/// Reads a whitespace-separated table of numbers, one row per non-empty
/// line, converting each row with `convert(row, path, line)`.
fn read_table<T>(
    path: &Path,
    convert: impl Fn(&[f64], &Path, usize) -> Result<T, ImportError>,
) -> Result<Vec<T>, ImportError> {
    let text = fs::read_to_string(path).map_err(|source| ImportError::Io {
        path: PathBuf::from(path),
        source,
    })?;
    let mut rows = Vec::new();
    for (index, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let values = line
            .split_whitespace()
            .map(|token| {
                token
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| ImportError::Parse {
                        path: path.to_owned(),
                        line: index + 1,
                        message: format!("`{token}` is not a finite number"),
                    })
            })
            .collect::<Result<Vec<f64>, _>>()?;
        rows.push(convert(&values, path, index + 1)?);
    }
    Ok(rows)
}
