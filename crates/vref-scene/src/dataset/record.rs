//! The serde shape of one dataset line, kept apart from the validated
//! types so that nothing unvalidated escapes this crate.

use std::fmt;
use std::marker::PhantomData;

use serde::de::value::MapAccessDeserializer;
use serde::de::{MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};

use crate::{Limits, PairError, SceneGraph, SceneObject, ScenePair, Side};

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PairRecord {
    pub name: String,
    #[serde(deserialize_with = "object")]
    pub robot: GraphRecord,
    #[serde(deserialize_with = "object")]
    pub human: GraphRecord,
    pub ground_truth: Vec<[u64; 2]>,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GraphRecord {
    #[serde(deserialize_with = "objects")]
    pub objects: Vec<ObjectRecord>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edges: Option<Vec<[u64; 2]>>,
    /// Which way is up in the camera frame; absent when unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<[f64; 3]>,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ObjectRecord {
    pub id: u64,
    pub position: [f64; 3],
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub feature: Vec<f32>,
    /// The sensor's stated position error per axis; absent when not
    /// stated (all zero).
    #[serde(default, skip_serializing_if = "all_zero")]
    pub position_sigma: [f64; 3],
}

fn all_zero(sigma: &[f64; 3]) -> bool {
    sigma.iter().all(|&s| s == 0.0)
}

/// A value that may only be read from a JSON object. Derived `Deserialize`
/// also accepts a struct written as an array of its field values in order
/// (`["name", {...}, {...}, []]`), which the dataset format does not allow.
pub(super) struct JsonObject<T>(pub T);

impl<'de, T: Deserialize<'de>> Deserialize<'de> for JsonObject<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ObjectVisitor<T>(PhantomData<T>);

        impl<'de, T: Deserialize<'de>> Visitor<'de> for ObjectVisitor<T> {
            type Value = T;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a JSON object")
            }

            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
                T::deserialize(MapAccessDeserializer::new(map))
            }
        }

        deserializer
            .deserialize_map(ObjectVisitor(PhantomData))
            .map(JsonObject)
    }
}

fn object<'de, D: Deserializer<'de>, T: Deserialize<'de>>(deserializer: D) -> Result<T, D::Error> {
    JsonObject::deserialize(deserializer).map(|JsonObject(value)| value)
}

fn objects<'de, D: Deserializer<'de>, T: Deserialize<'de>>(
    deserializer: D,
) -> Result<Vec<T>, D::Error> {
    let list = Vec::<JsonObject<T>>::deserialize(deserializer)?;
    Ok(list.into_iter().map(|JsonObject(value)| value).collect())
}

impl PairRecord {
    pub fn from_pair(pair: &ScenePair) -> Self {
        Self {
            name: pair.name.clone(),
            robot: GraphRecord::from_graph(&pair.robot),
            human: GraphRecord::from_graph(&pair.human),
            ground_truth: pair.ground_truth.iter().map(|&(h, r)| [h, r]).collect(),
        }
    }

    pub fn into_pair(self, limits: &Limits) -> Result<ScenePair, PairError> {
        let robot = self
            .robot
            .into_graph(limits)
            .map_err(ScenePair::graph_error(Side::Robot))?;
        let human = self
            .human
            .into_graph(limits)
            .map_err(ScenePair::graph_error(Side::Human))?;
        let ground_truth = self.ground_truth.into_iter().map(|[h, r]| (h, r)).collect();
        ScenePair::new(self.name, robot, human, ground_truth)
    }
}

impl GraphRecord {
    fn from_graph(graph: &SceneGraph) -> Self {
        Self {
            objects: graph
                .objects()
                .iter()
                .map(|o| ObjectRecord {
                    id: o.id,
                    position: o.position.coords.into(),
                    feature: o.feature.clone(),
                    position_sigma: o.position_sigma,
                })
                .collect(),
            edges: graph.edge_ids(),
            up: graph.up().map(Into::into),
        }
    }

    fn into_graph(self, limits: &Limits) -> Result<SceneGraph, crate::GraphError> {
        let objects = self
            .objects
            .into_iter()
            .map(|o| SceneObject::new(o.id, o.position, o.feature).with_sigma(o.position_sigma))
            .collect();
        SceneGraph::new(objects, self.edges, limits)?.with_up(self.up)
    }
}
