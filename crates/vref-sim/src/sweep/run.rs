//! Running a sweep: generate, evaluate, summarise per (method, level).

use std::time::Duration;

use vref_match::{Evaluation, Method, Params, Summary};

use crate::{Generator, NoiseSweep, SimConfig, SweepError};

/// What to sweep and over what.
#[derive(Debug, Clone)]
pub struct Sweep {
    pub noise: NoiseSweep,
    /// The configuration whose noise is scaled (a preset's, say).
    pub base: SimConfig,
    /// Scene name prefix, as [`Generator::named`] takes it.
    pub name: String,
    /// Factors on the base configuration's noise, in the order reported;
    /// each finite and at least 0.
    pub levels: Vec<f64>,
    /// Scenes per level, at least 1.
    pub count: u64,
    pub seed: u64,
    /// At least one.
    pub methods: Vec<Method>,
    pub params: Params,
}

/// One method's result at one level.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepPoint {
    pub method: Method,
    pub level: f64,
    pub summary: Summary,
    /// Mean wall time of building the affinities, solving and discretising.
    pub mean_solve: Duration,
}

impl Sweep {
    /// Refuses a plan that cannot run, before any scene is generated:
    /// levels, count, methods, matching parameters and the configuration
    /// at every level.
    pub fn validate(&self) -> Result<(), SweepError> {
        if self.levels.is_empty() {
            return Err(SweepError::NoLevels);
        }
        if let Some((index, &value)) = self
            .levels
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(SweepError::BadLevel { index, value });
        }
        if self.count == 0 {
            return Err(SweepError::NoScenes);
        }
        if self.methods.is_empty() {
            return Err(SweepError::NoMethods);
        }
        self.params.validate().map_err(SweepError::Params)?;
        for &level in &self.levels {
            self.generator(level)?;
        }
        Ok(())
    }

    /// Every point, level by level and within a level in the order of
    /// `methods`.
    pub fn run(&self) -> Result<Vec<SweepPoint>, SweepError> {
        self.run_with(|| {})
    }

    /// [`Sweep::run`], calling `on_scene` after each scene is evaluated
    /// (for a progress display).
    pub fn run_with(&self, mut on_scene: impl FnMut()) -> Result<Vec<SweepPoint>, SweepError> {
        self.validate()?;
        let mut points = Vec::with_capacity(self.levels.len() * self.methods.len());
        for &level in &self.levels {
            let generator = self.generator(level)?;
            let mut evaluation =
                Evaluation::new(&self.methods, self.params).map_err(SweepError::Params)?;
            // One scene at a time: a long sweep never holds its scenes.
            for scene in generator.scenes(self.count) {
                let pair = scene
                    .map_err(|source| SweepError::Scene { level, source })?
                    .pair;
                evaluation.add(&pair).map_err(|source| SweepError::Match {
                    level,
                    scene: pair.name.clone(),
                    source,
                })?;
                on_scene();
            }
            points.extend(evaluation.reports().into_iter().map(|r| SweepPoint {
                method: r.method,
                level,
                summary: r.summary,
                mean_solve: r.mean_solve,
            }));
        }
        Ok(points)
    }

    /// Scenes the whole sweep evaluates.
    pub fn total_scenes(&self) -> u64 {
        self.count.saturating_mul(self.levels.len() as u64)
    }

    fn generator(&self, level: f64) -> Result<Generator, SweepError> {
        let config = self.noise.scaled(&self.base, level);
        Generator::new(config, self.seed)
            .map(|g| g.named(&self.name))
            .map_err(|source| SweepError::Config { level, source })
    }
}

/// Accuracy against level, one curve per method in order of first
/// appearance: the series of a line plot.
pub fn accuracy_curves(points: &[SweepPoint]) -> Vec<(Method, Vec<(f64, f64)>)> {
    let mut curves: Vec<(Method, Vec<(f64, f64)>)> = Vec::new();
    for p in points {
        let point = (p.level, p.summary.accuracy.mean);
        match curves.iter_mut().find(|(m, _)| *m == p.method) {
            Some((_, curve)) => curve.push(point),
            None => curves.push((p.method, vec![point])),
        }
    }
    curves
}
