use std::time::{Duration, Instant};

use vref_scene::ScenePair;

use crate::calibration::ECE_BINS;
use crate::{
    MatchError, Method, OkRule, Params, Problem, SceneScore, SolveOptions, Summary, Tier, Verdict,
    expected_calibration_error, score_scene, solve_with,
};

/// Scores of several methods accumulated scene by scene.
#[derive(Debug, Clone)]
pub struct Evaluation {
    params: Params,
    tier: Tier,
    methods: Vec<Method>,
    scores: Vec<Vec<SceneScore>>,
    solve_times: Vec<Duration>,
    /// Per method, every human object's answer with its confidence.
    answers: Vec<Vec<RowAnswer>>,
    /// What makes an answer's status `ok`.
    ok_rule: OkRule,
}

/// One human object's answer in one scene.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RowAnswer {
    /// Index of the scene in the order added.
    pub scene: usize,
    pub row: usize,
    /// The method's confidence that this answer is right.
    pub confidence: f64,
    /// The status the live matcher gives this answer (before staleness).
    pub status: Verdict,
    /// The pair's squared residual in units of the stated errors, where
    /// tested ([`crate::pair_residuals`]).
    pub residual: Option<f64>,
    /// The human object's id, and the robot object's id the method gave
    /// it as partner (if any): where a reader checks answers against a
    /// truth of its own (e.g. positions under known camera poses).
    pub human_object: u64,
    pub partner: Option<u64>,
    /// Whether it is right ("no partner" for an object without one counts).
    pub correct: bool,
    /// Whether the method gave the object a partner.
    pub matched: bool,
    /// Object counts of the scene's human and robot views.
    pub human_objects: usize,
    pub robot_objects: usize,
    /// The method's margin of its motion over chance, where it has one.
    pub margin: Option<f64>,
    /// The method's significance of its motion against chance, where it
    /// has one (`-log10` of its false alarms).
    pub significance: Option<f64>,
    /// The method's fit of its motion (its score over the largest
    /// possible), where it has one.
    pub fit: Option<f64>,
    /// Share of both views' objects the method's motion says the other
    /// camera should have seen and did not ([`crate::unseen_share`]).
    pub unseen: Option<f64>,
}

/// One method's result over all scenes added.
#[derive(Debug, Clone, PartialEq)]
pub struct MethodReport {
    pub method: Method,
    pub summary: Summary,
    /// Mean wall time of building the affinities, solving and discretising.
    pub mean_solve: Duration,
    /// Expected calibration error of the confidence over every human
    /// object of every scene (`ECE_BINS` equal-width bins).
    pub ece: f64,
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
            answers: vec![Vec::new(); methods.len()],
            ok_rule: OkRule::default(),
        })
    }

    /// Gives each answer the status `rule` decides (default
    /// [`OkRule::default`]): the matcher's, given its `[matcher]` settings.
    pub fn with_ok_rule(mut self, rule: OkRule) -> Self {
        self.ok_rule = rule;
        self
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
        let truth: std::collections::HashMap<u64, u64> =
            pair.ground_truth.iter().copied().collect();
        let scene = self.scenes();
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
            let unseen =
                crate::unseen_share(&problem, &solution.assignment, solution.motion.as_ref());
            for (row, (a, &confidence)) in solution
                .assignment
                .iter()
                .zip(&solution.confidence)
                .enumerate()
            {
                let guess = a.map(|j| pair.robot.objects()[j].id);
                self.answers[k].push(RowAnswer {
                    scene,
                    row,
                    confidence,
                    status: solution.verdict(row, confidence, &self.ok_rule),
                    residual: solution.residuals.get(row).copied().flatten(),
                    human_object: human_ids[row],
                    partner: guess,
                    correct: guess == truth.get(&human_ids[row]).copied(),
                    matched: a.is_some(),
                    human_objects: pair.human.len(),
                    robot_objects: pair.robot.len(),
                    margin: solution.margin,
                    significance: solution.significance,
                    fit: solution.fit,
                    unseen,
                });
            }
            self.scores[k].push(score_scene(&human_ids, &predicted, &pair.ground_truth));
        }
        Ok(())
    }

    /// Scenes added so far.
    pub fn scenes(&self) -> usize {
        self.scores.first().map_or(0, Vec::len)
    }

    /// Every human object's answer by `method`, in the order added.
    pub fn answers(&self, method: Method) -> &[RowAnswer] {
        self.methods
            .iter()
            .position(|&m| m == method)
            .map_or(&[], |k| &self.answers[k])
    }

    pub fn reports(&self) -> Vec<MethodReport> {
        let scenes = self.scenes().max(1) as u32;
        self.methods
            .iter()
            .zip(&self.scores)
            .zip(&self.solve_times)
            .zip(&self.answers)
            .map(|(((&method, scores), &total), answers)| {
                let pairs: Vec<(f64, bool)> =
                    answers.iter().map(|a| (a.confidence, a.correct)).collect();
                MethodReport {
                    method,
                    summary: Summary::from_scores(scores),
                    mean_solve: total / scenes,
                    ece: expected_calibration_error(&pairs, ECE_BINS),
                }
            })
            .collect()
    }
}
