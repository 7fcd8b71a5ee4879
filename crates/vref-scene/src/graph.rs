use std::collections::HashMap;

use nalgebra::{Point3, Vector3};

use crate::{GraphError, Limits};

/// One object as a camera sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObject {
    /// Track id, stable over time within one view; ids of the two views are
    /// unrelated.
    pub id: u64,
    /// Position in the camera's own frame (metres for live scenes, pixels
    /// for image data sets: the matcher only uses distances).
    pub position: Point3<f64>,
    /// Appearance feature; empty means "no appearance information".
    pub feature: Vec<f32>,
    /// Standard deviation of the position error along each axis of the
    /// camera frame, as the sensor states it; all zero when not stated
    /// (a dataset file carries it only where its line states it).
    pub position_sigma: [f64; 3],
}

impl SceneObject {
    pub fn new(id: u64, position: [f64; 3], feature: Vec<f32>) -> Self {
        Self {
            id,
            position: Point3::from(position),
            feature,
            position_sigma: [0.0; 3],
        }
    }

    /// The object with the sensor's stated position error.
    pub fn with_sigma(self, position_sigma: [f64; 3]) -> Self {
        Self {
            position_sigma,
            ..self
        }
    }
}

/// A validated graph of one view: unique ids, finite positions within the
/// limits, one feature dimension, edges between known objects.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneGraph {
    objects: Vec<SceneObject>,
    /// Undirected edges as (smaller index, larger index), sorted and without
    /// repeats; `None` means fully connected.
    edges: Option<Vec<(usize, usize)>>,
    feature_dim: usize,
    index: HashMap<u64, usize>,
    /// Which way is up (against gravity) in the camera's frame, unit
    /// length; `None` when the view does not know.
    up: Option<Vector3<f64>>,
}

impl SceneGraph {
    /// Validates `objects` and the optional edge list (pairs of object ids).
    pub fn new(
        objects: Vec<SceneObject>,
        edges: Option<Vec<[u64; 2]>>,
        limits: &Limits,
    ) -> Result<Self, GraphError> {
        if objects.is_empty() && limits.require_objects {
            return Err(GraphError::Empty);
        }
        if objects.len() > limits.capacity {
            return Err(GraphError::TooManyObjects {
                count: objects.len(),
                capacity: limits.capacity,
            });
        }
        let feature_dim = objects.first().map_or(0, |o| o.feature.len());
        let mut index = HashMap::with_capacity(objects.len());
        for (i, object) in objects.iter().enumerate() {
            check_object(object, feature_dim, limits)?;
            if index.insert(object.id, i).is_some() {
                return Err(GraphError::DuplicateId { id: object.id });
            }
        }
        let edges = edges.map(|list| edge_indices(&list, &index)).transpose()?;
        Ok(Self {
            objects,
            edges,
            feature_dim,
            index,
            up: None,
        })
    }

    /// This graph with its camera's up vector (against gravity, in the
    /// camera frame; any non-zero length, kept as unit length), or with
    /// none (`None`: unknown).
    pub fn with_up(self, up: Option<[f64; 3]>) -> Result<Self, GraphError> {
        let up = up.map(check_up).transpose()?;
        Ok(Self { up, ..self })
    }

    /// Which way is up in the camera frame (unit length), where known.
    pub fn up(&self) -> Option<Vector3<f64>> {
        self.up
    }

    pub fn objects(&self) -> &[SceneObject] {
        &self.objects
    }

    pub fn len(&self) -> usize {
        self.objects.len()
    }

    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// Undirected edges by object index, or `None` when fully connected.
    pub fn edges(&self) -> Option<&[(usize, usize)]> {
        self.edges.as_deref()
    }

    /// Dimension of every feature of this graph (0: no features).
    pub fn feature_dim(&self) -> usize {
        self.feature_dim
    }

    /// Index of the object with track id `id`.
    pub fn index_of(&self, id: u64) -> Option<usize> {
        self.index.get(&id).copied()
    }

    /// This graph with every track id raised by `offset`, its edges with
    /// them: the same scene under new ids, as a tracker that restarted
    /// would report it.
    pub fn with_ids_raised(&self, offset: u64, limits: &Limits) -> Result<Self, GraphError> {
        let raise = |id: u64| {
            id.checked_add(offset)
                .ok_or(GraphError::IdOverflow { id, offset })
        };
        let objects = self
            .objects
            .iter()
            .map(|o| {
                Ok(SceneObject {
                    id: raise(o.id)?,
                    ..o.clone()
                })
            })
            .collect::<Result<Vec<_>, GraphError>>()?;
        let edges = self
            .edge_ids()
            .map(|list| {
                list.iter()
                    .map(|&[a, b]| Ok([raise(a)?, raise(b)?]))
                    .collect::<Result<Vec<_>, GraphError>>()
            })
            .transpose()?;
        Self::new(objects, edges, limits).map(|g| Self { up: self.up, ..g })
    }

    /// The edge list by object ids, as a dataset file holds it.
    pub fn edge_ids(&self) -> Option<Vec<[u64; 2]>> {
        self.edges.as_ref().map(|edges| {
            edges
                .iter()
                .map(|&(i, j)| [self.objects[i].id, self.objects[j].id])
                .collect()
        })
    }
}

/// Lengths below this are no direction (a float32 wire value rounds a
/// unit vector's length to within 1e-7 of 1).
const MIN_UP_NORM: f64 = 1e-6;

fn check_up(up: [f64; 3]) -> Result<Vector3<f64>, GraphError> {
    let v = Vector3::from(up);
    let norm = v.norm();
    if !(v.iter().all(|c| c.is_finite()) && norm >= MIN_UP_NORM && norm.is_finite()) {
        return Err(GraphError::BadUp { up });
    }
    Ok(v / norm)
}

fn check_object(
    object: &SceneObject,
    feature_dim: usize,
    limits: &Limits,
) -> Result<(), GraphError> {
    let id = object.id;
    for (axis, &value) in object.position.coords.iter().enumerate() {
        if !value.is_finite() {
            return Err(GraphError::NonFinitePosition { id, axis, value });
        }
        if value.abs() > limits.max_abs_coordinate {
            return Err(GraphError::AbsurdPosition {
                id,
                axis,
                value,
                limit: limits.max_abs_coordinate,
            });
        }
    }
    for (axis, &value) in object.position_sigma.iter().enumerate() {
        if !(value.is_finite() && value >= 0.0) {
            return Err(GraphError::BadPositionSigma { id, axis, value });
        }
    }
    if object.feature.len() != feature_dim {
        return Err(GraphError::FeatureDimMismatch {
            id,
            expected: feature_dim,
            found: object.feature.len(),
        });
    }
    if let Some((index, &value)) = object
        .feature
        .iter()
        .enumerate()
        .find(|(_, v)| !v.is_finite())
    {
        return Err(GraphError::NonFiniteFeature { id, index, value });
    }
    Ok(())
}

fn edge_indices(
    list: &[[u64; 2]],
    index: &HashMap<u64, usize>,
) -> Result<Vec<(usize, usize)>, GraphError> {
    let mut edges = Vec::with_capacity(list.len());
    for &[a, b] in list {
        if a == b {
            return Err(GraphError::SelfLoop { id: a });
        }
        let lookup = |id: u64| {
            index
                .get(&id)
                .copied()
                .ok_or(GraphError::UnknownEdgeEndpoint { a, b, unknown: id })
        };
        let (i, j) = (lookup(a)?, lookup(b)?);
        edges.push((i.min(j), i.max(j)));
    }
    edges.sort_unstable();
    edges.dedup();
    Ok(edges)
}
