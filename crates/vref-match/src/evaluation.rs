use std::time::{Duration, Instant};

use vref_scene::ScenePair;

use crate::{MatchError, Method, Params, Problem, SceneScore, Summary, score_scene, solve};

/// Scores of several methods accumulated scene by scene.
#[derive(Debug, Clone)]
pub struct Evaluation {
    params: Params,
    methods: Vec<Method>,
    scores: Vec<Vec<SceneScore>>,
    solve_times: Vec<Duration>,
}

/// One method's result over all scenes added.
#[derive(Debug, Clone, PartialEq)]
pub struct MethodReport {
    pub method: Method,
    pub summary: Summary,
    /// Mean wall time of building the affinities, solving and discretising.
    pub mean_solve: Duration,
}

impl Evaluation {
    pub fn new(methods: &[Method], params: Params) -> Result<Self, MatchError> {
        params.validate()?;
        Ok(Self {
            params,
            methods: methods.to_vec(),
            scores: vec![Vec::new(); methods.len()],
            solve_times: vec![Duration::ZERO; methods.len()],
        })
    }

    /// Matches `pair` with every method and records its scores.
    pub fn add(&mut self, pair: &ScenePair) -> Result<(), MatchError> {
        let human_ids: Vec<u64> = pair.human.objects().iter().map(|o| o.id).collect();
        for (k, &method) in self.methods.iter().enumerate() {
            let start = Instant::now();
            let problem = Problem::new(&pair.human, &pair.robot, self.params.beta)?;
            let solution = solve(method, &problem, &self.params)?;
            self.solve_times[k] += start.elapsed();
            let predicted = solution.id_pairs(&pair.human, &pair.robot);
            self.scores[k].push(score_scene(&human_ids, &predicted, &pair.ground_truth));
        }
        Ok(())
    }

    /// Scenes added so far.
    pub fn scenes(&self) -> usize {
        self.scores.first().map_or(0, Vec::len)
    }

    pub fn reports(&self) -> Vec<MethodReport> {
        let scenes = self.scenes().max(1) as u32;
        self.methods
            .iter()
            .zip(&self.scores)
            .zip(&self.solve_times)
            .map(|((&method, scores), &total)| MethodReport {
                method,
                summary: Summary::from_scores(scores),
                mean_solve: total / scenes,
            })
            .collect()
    }
}
