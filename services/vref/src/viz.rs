use std::fs::File;
use std::io::BufReader;

use anyhow::Context;
use vref_config::Config;
use vref_match::{Problem, solve};
use vref_scene::DatasetReader;
use vref_viz::{MatchPicture, RenderError, Size, find_scene};

use crate::cli::VizArgs;
use crate::failure::{Blame, Failure};

pub fn run(args: &VizArgs) -> Result<(), Failure> {
    let (config, source) = Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    let mut params = config.matching;
    if let Some(beta) = args.beta {
        params.beta = beta;
    }
    params.validate().context("--beta").bad_input()?;

    let file = File::open(&args.dataset)
        .with_context(|| format!("opening {}", args.dataset.display()))
        .bad_input()?;
    let scenes = DatasetReader::new(BufReader::new(file), config.scene.limits());
    let pair = find_scene(scenes, &args.scene)
        .with_context(|| format!("reading {}", args.dataset.display()))
        .bad_input()?;
    let solution = Problem::new(&pair.human, &pair.robot, params.beta)
        .and_then(|problem| solve(args.method, &problem, &params))
        .with_context(|| format!("scene {:?}", pair.name))
        .bad_input()?;
    let predicted = solution.id_pairs(&pair.human, &pair.robot);

    let size = Size::new(args.width, args.height);
    MatchPicture::new(&pair, &predicted, args.method.name())
        .projection(args.projection)
        .save(&args.out, size)
        .map_err(blame)?;
    tracing::info!(out = %args.out.display(), scene = pair.name, "picture written");
    Ok(())
}

fn blame(error: RenderError) -> Failure {
    let bad_input = matches!(error, RenderError::BadSize { .. });
    let error = anyhow::Error::new(error).context("drawing the picture");
    if bad_input {
        Failure::BadInput(error)
    } else {
        Failure::Runtime(error)
    }
}
