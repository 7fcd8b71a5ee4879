use vref_scene::SceneGraph;

/// One object of a view as the engine keeps it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Tracked {
    pub id: u64,
    pub position: [f64; 3],
    /// The stated position error per axis.
    pub sigma: [f64; 3],
    pub feature: Vec<f32>,
    pub norm: f64,
}

/// What an update did to a view, by track id.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Change {
    /// Objects with a track id the view did not have.
    pub added: usize,
    /// Track ids the view no longer has.
    pub removed: usize,
    /// Objects whose position or feature changed.
    pub changed: usize,
    /// Objects exactly as they were.
    pub kept: usize,
}

impl Change {
    /// Whether anything changed.
    pub fn any(&self) -> bool {
        self.added + self.removed + self.changed > 0
    }
}

/// One side's objects and their distance matrix.
#[derive(Debug, Clone, Default)]
pub(super) struct View {
    pub objects: Vec<Tracked>,
    /// Which way is up in the camera frame, where the view knows.
    pub up: Option<nalgebra::Vector3<f64>>,
    /// `n x n`, row-major.
    pub distances: Vec<f64>,
}

impl View {
    pub fn len(&self) -> usize {
        self.objects.len()
    }

    pub fn has_features(&self) -> bool {
        self.objects.first().is_some_and(|o| !o.feature.is_empty())
    }

    /// Replaces the objects with `graph`'s. Returns, for every new object,
    /// its index before the update if it is unchanged, and what changed.
    /// Distances between two unchanged objects are copied, not recomputed.
    pub fn update(&mut self, graph: &SceneGraph) -> (Vec<Option<usize>>, Change) {
        let ids: Vec<u64> = self.objects.iter().map(|o| o.id).collect();
        let before = super::index_by_id(&ids);
        let objects: Vec<Tracked> = graph
            .objects()
            .iter()
            .map(|o| {
                let norm = crate::appearance::norm(&o.feature);
                Tracked {
                    id: o.id,
                    position: [o.position.x, o.position.y, o.position.z],
                    sigma: o.position_sigma,
                    feature: o.feature.clone(),
                    norm,
                }
            })
            .collect();
        let mut change = Change::default();
        let unchanged: Vec<Option<usize>> = objects
            .iter()
            .map(|o| match before.get(&o.id) {
                None => {
                    change.added += 1;
                    None
                }
                Some(&k) if self.objects[k] == *o => {
                    change.kept += 1;
                    Some(k)
                }
                Some(_) => {
                    change.changed += 1;
                    None
                }
            })
            .collect();
        change.removed = self.objects.len() - change.kept - change.changed;
        let (n, old_n) = (objects.len(), self.objects.len());
        let mut distances = vec![0.0; n * n];
        for i in 0..n {
            for j in i + 1..n {
                let d = match (unchanged[i], unchanged[j]) {
                    (Some(oi), Some(oj)) => self.distances[oi * old_n + oj],
                    _ => distance(&objects[i].position, &objects[j].position),
                };
                distances[i * n + j] = d;
                distances[j * n + i] = d;
            }
        }
        self.objects = objects;
        self.distances = distances;
        (unchanged, change)
    }
}

fn distance(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    p.iter()
        .zip(q)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}
