//! Objects as the wire carries them: fixed-size entries with the feature
//! inline. A feature longer than the wire's maximum is an error, never
//! cut short.

use vref_scene::SceneGraph;
use vref_sim::LiveView;
use vref_wire::{MAX_FEATURE_DIM, ObjectEntry};

use crate::EntryError;

/// One wire entry; positions and uncertainties in metres (or the source's
/// own units).
pub fn entry(
    id: u64,
    position: [f64; 3],
    sigma: [f64; 3],
    feature: &[f32],
) -> Result<ObjectEntry, EntryError> {
    let mut inline = [0.0; MAX_FEATURE_DIM];
    inline
        .get_mut(..feature.len())
        .ok_or(EntryError::FeatureTooLong {
            id,
            dim: feature.len(),
            max: MAX_FEATURE_DIM,
        })?
        .copy_from_slice(feature);
    // The wire carries single precision.
    Ok(ObjectEntry {
        track_id: id,
        position: position.map(|v| v as f32),
        position_sigma: sigma.map(|v| v as f32),
        feature: inline,
    })
}

/// A feature dimension the wire can carry.
pub fn check_dim(dim: usize) -> Result<usize, EntryError> {
    if dim > MAX_FEATURE_DIM {
        return Err(EntryError::FeatureDimTooLong {
            dim,
            max: MAX_FEATURE_DIM,
        });
    }
    Ok(dim)
}

/// A graph's objects, with their stated position errors.
pub fn graph_entries(graph: &SceneGraph) -> Result<Vec<ObjectEntry>, EntryError> {
    check_dim(graph.feature_dim())?;
    graph
        .objects()
        .iter()
        .map(|o| entry(o.id, o.position.coords.into(), o.position_sigma, &o.feature))
        .collect()
}

/// A live view's objects, written into `out` (cleared first) so that one
/// buffer serves every frame.
pub fn view_entries(view: &LiveView, out: &mut Vec<ObjectEntry>) -> Result<(), EntryError> {
    out.clear();
    for o in &view.objects {
        out.push(entry(o.id, o.position.coords.into(), o.sigma, &o.feature)?);
    }
    Ok(())
}
