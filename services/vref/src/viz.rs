use std::fs::File;
use std::io::BufReader;

use std::path::Path;

use anyhow::{Context, anyhow};
use vref_config::Config;
use vref_import::{BopDataset, BopOptions, BopScene, MeasuredView, outline};
use vref_logging::exit::{Blame, Failure};
use vref_match::{Method, Params, Problem, solve};
use vref_scene::{DatasetReader, ScenePair};
use vref_viz::{
    ImageMatchPicture, ImageObject, MatchPicture, RenderError, Size, ViewImage, find_scene,
};

use crate::cli::VizArgs;

pub fn run(args: &VizArgs) -> Result<(), Failure> {
    let (config, source) = Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    let mut params = config.matching;
    if let Some(beta) = args.beta {
        params.beta = beta;
    }
    params.validate().context("--beta").bad_input()?;
    if let Some(dir) = &args.bop {
        return bop(args, dir, &config, &params);
    }
    let Some(dataset) = &args.dataset else {
        return Err(anyhow!("give --dataset or --bop")).bad_input();
    };
    let file = File::open(dataset)
        .with_context(|| format!("opening {}", dataset.display()))
        .bad_input()?;
    let scenes = DatasetReader::new(BufReader::new(file), config.scene.limits());
    let pair = find_scene(scenes, &args.scene)
        .with_context(|| format!("reading {}", dataset.display()))
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

/// The scene `args.scene` of the BOP dataset at `dir`, measured and
/// matched, drawn over its two images.
fn bop(args: &VizArgs, dir: &Path, config: &Config, params: &Params) -> Result<(), Failure> {
    let dataset = BopDataset::open(dir, "test").bad_input()?;
    let scene_dir = dataset
        .scenes()
        .iter()
        .find(|s| dataset.scene_name(s) == args.scene)
        .with_context(|| {
            let first = dataset.scenes().first().map(|s| dataset.scene_name(s));
            format!(
                "no scene {:?} in {} (scenes are named like {})",
                args.scene,
                dir.display(),
                first.unwrap_or_default()
            )
        })
        .bad_input()?;
    let options = BopOptions {
        robot_image: 0,
        human_image: 1,
        perception: config.perception,
        world_up: None,
    };
    let scene = BopScene::measure(&dataset, scene_dir, &options).bad_input()?;
    let pair = scene.pair(&config.scene.limits()).bad_input()?;
    let predicted = matched(&pair, args.method, params)?;
    let human_view = scene_dir
        .load_view(options.human_image, config.perception.image_limit())
        .bad_input()?;
    let robot_view = scene_dir
        .load_view(options.robot_image, config.perception.image_limit())
        .bad_input()?;
    let human = view_image(&human_view, &scene.human);
    let robot = view_image(&robot_view, &scene.robot);
    ImageMatchPicture::new(&pair, &predicted, args.method.name(), &human, &robot)
        .save(&args.out)
        .map_err(blame)?;
    tracing::info!(out = %args.out.display(), scene = pair.name, "picture written");
    Ok(())
}

fn matched(pair: &ScenePair, method: Method, params: &Params) -> Result<Vec<(u64, u64)>, Failure> {
    let solution = Problem::new(&pair.human, &pair.robot, params.beta)
        .and_then(|problem| solve(method, &problem, params))
        .with_context(|| format!("scene {:?}", pair.name))
        .bad_input()?;
    Ok(solution.id_pairs(&pair.human, &pair.robot))
}

/// A view's image with its measured objects: outlines of their masks and
/// the pixel each is seen at.
fn view_image<'a>(view: &'a vref_import::BopView, measured: &MeasuredView) -> ViewImage<'a> {
    let objects = measured
        .detections
        .iter()
        .zip(&measured.instances)
        .filter_map(|(d, &k)| {
            Some(ImageObject {
                id: d.id,
                centre: view.intrinsics.project(d.position).unwrap_or([0.0, 0.0]),
                outline: outline(view.masks.get(k?)?),
            })
        })
        .collect();
    let (width, height) = view.colour.dimensions();
    ViewImage {
        rgb: view.colour.as_raw(),
        width,
        height,
        objects,
    }
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
