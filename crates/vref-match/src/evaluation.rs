use std::time::{Duration, Instant};

use vref_scene::ScenePair;

use crate::{
    MatchError, Method, Params, Problem, SceneScore, SolveOptions, Summary, Tier, score_scene,
    solve_with,
};

/// Scores of several methods accumulated scene by scene.
#[derive(Debug, Clone)]
pub struct Evaluation {
    params: Params,
    tier: Tier,
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
            tier: Tier::Exact,
            methods: methods.to_vec(),
            scores: vec![Vec::new(); methods.len()],
            solve_times: vec![Duration::ZERO; methods.len()],
        })
    }

    /// Runs the methods in `tier` (default exact). The live tier starts
    /// every scene cold: scenes of a dataset are unrelated.
    pub fn with_tier(mut self, tier: Tier) -> Self {
        self.tier = tier;
        self
    }

    /// Matches `pair` with every method and records its scores.
    pub fn add(&mut self, pair: &ScenePair) -> Result<(), MatchError> {
        let human_ids: Vec<u64> = pair.human.objects().iter().map(|o| o.id).collect();
        for (k, &method) in self.methods.iter().enumerate() {
            let start = Instant::now();
            let (problem, options) = match self.tier {
                Tier::Exact => (
                    Problem::new(&pair.human, &pair.robot, self.params.beta)?,
                    SolveOptions::default(),
                ),
                Tier::Live => (
                    Problem::live(&pair.human, &pair.robot, &self.params)?,
                    SolveOptions {
                        warm_start: None,
                        stop_when_stable: Some(self.params.live.stable_iterations),
                    },
                ),
            };
            let params = match self.tier {
                Tier::Exact => self.params,
                Tier::Live => self.params.for_live(),
            };
            let solution = solve_with(method, &problem, &params, options)?;
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
