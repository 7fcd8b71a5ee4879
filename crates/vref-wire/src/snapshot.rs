use nalgebra::{Point3, Unit, Vector3};
use vref_scene::{Limits, SceneGraph, SceneObject, Side};

use crate::{
    MAX_FEATURE_DIM, ObjectEntry, PointingRay, SCHEMA_VERSION, SideCode, SnapshotHeader, WireError,
};

/// A snapshot that passed every check, as scene types.
#[derive(Debug, Clone, PartialEq)]
pub struct ValidSnapshot {
    pub side: Side,
    pub session: u64,
    pub sequence: u64,
    pub timestamp_ns: u64,
    pub frame_name: String,
    pub graph: SceneGraph,
}

/// Checks a snapshot read in place from shared memory and converts it.
/// `expected` is the side whose service it arrived on.
pub fn validate_snapshot(
    header: &SnapshotHeader,
    entries: &[ObjectEntry],
    expected: Side,
    limits: &Limits,
) -> Result<ValidSnapshot, WireError> {
    if header.schema_version != SCHEMA_VERSION {
        return Err(WireError::SchemaVersion {
            found: header.schema_version,
            expected: SCHEMA_VERSION,
        });
    }
    let side = side_of(header.side)?;
    if side != expected {
        return Err(WireError::WrongSide {
            expected,
            found: side,
        });
    }
    let count = header.object_count as usize;
    if count > entries.len() {
        return Err(WireError::CountExceedsSlice {
            count: header.object_count,
            slice: entries.len(),
        });
    }
    let dim = header.feature_dim as usize;
    if dim > MAX_FEATURE_DIM {
        return Err(WireError::FeatureDimTooLarge {
            dim: header.feature_dim,
            max: MAX_FEATURE_DIM,
        });
    }
    let frame_name = frame_name(&header.frame_name)?;
    // Refuse before converting anything, so a huge count costs nothing.
    if count > limits.capacity {
        return Err(vref_scene::GraphError::TooManyObjects {
            count,
            capacity: limits.capacity,
        }
        .into());
    }
    let objects = entries[..count]
        .iter()
        .map(|e| object_of(e, dim))
        .collect::<Result<Vec<_>, _>>()?;
    // Checked by with_up (finite, not zero) and kept at unit length.
    let up = header.up().map(|v| v.map(f64::from));
    let graph = SceneGraph::new(objects, None, limits)?.with_up(up)?;
    Ok(ValidSnapshot {
        side,
        session: header.session,
        sequence: header.sequence,
        timestamp_ns: header.timestamp_ns,
        frame_name,
        graph,
    })
}

/// A graph's up vector as a snapshot header carries it (single
/// precision), for publishers.
pub fn wire_up(graph: &SceneGraph) -> Option<[f32; 3]> {
    graph.up().map(|v| [v.x as f32, v.y as f32, v.z as f32])
}

fn side_of(code: u32) -> Result<Side, WireError> {
    match code {
        c if c == SideCode::Robot as u32 => Ok(Side::Robot),
        c if c == SideCode::Human as u32 => Ok(Side::Human),
        other => Err(WireError::UnknownSide(other)),
    }
}

fn frame_name(bytes: &[u8]) -> Result<String, WireError> {
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    std::str::from_utf8(&bytes[..end])
        .map(str::to_owned)
        .map_err(|_| WireError::FrameNameNotUtf8)
}

fn object_of(entry: &ObjectEntry, dim: usize) -> Result<SceneObject, WireError> {
    if let Some(&value) = entry
        .position_sigma
        .iter()
        .find(|s| !(s.is_finite() && **s >= 0.0))
    {
        return Err(WireError::BadUncertainty {
            id: entry.track_id,
            value,
        });
    }
    let [x, y, z] = entry.position.map(f64::from);
    // Position and feature are checked by SceneGraph::new.
    Ok(
        SceneObject::new(entry.track_id, [x, y, z], entry.feature[..dim].to_vec())
            .with_sigma(entry.position_sigma.map(f64::from)),
    )
}

/// A pointing ray that passed every check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub session: u64,
    pub sequence: u64,
    pub timestamp_ns: u64,
    pub origin: Point3<f64>,
    pub direction: Unit<Vector3<f64>>,
    pub cone_half_angle: f64,
    pub confidence: f64,
}

impl PointingRay {
    /// Checks a ray read from shared memory.
    pub fn validate(&self) -> Result<Ray, WireError> {
        if self.schema_version != SCHEMA_VERSION {
            return Err(WireError::SchemaVersion {
                found: self.schema_version,
                expected: SCHEMA_VERSION,
            });
        }
        let finite = |v: &[f32; 3], field| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(Vector3::from(v.map(f64::from)))
            } else {
                Err(WireError::NonFiniteRay { field })
            }
        };
        let origin = finite(&self.origin, "origin")?;
        let direction = finite(&self.direction, "direction")?;
        let direction = Unit::try_new(direction, 1e-9).ok_or(WireError::ZeroRayDirection)?;
        let angle = self.cone_half_angle;
        if !(angle > 0.0 && f64::from(angle) <= std::f64::consts::FRAC_PI_2) {
            return Err(WireError::BadConeAngle(angle));
        }
        if !(0.0..=1.0).contains(&self.confidence) {
            return Err(WireError::BadConfidence(self.confidence));
        }
        Ok(Ray {
            session: self.session,
            sequence: self.sequence,
            timestamp_ns: self.timestamp_ns,
            origin: Point3::from(origin),
            direction,
            cone_half_angle: f64::from(angle),
            confidence: f64::from(self.confidence),
        })
    }
}
