//! `vref demo`: its arguments to vref_harness::demo, each answer's line
//! and the summary printed.

use vref_config::Config;
use vref_harness::demo::{self, DemoOptions};
use vref_logging::exit::{Blame, Failure};

use crate::cli::DemoArgs;
use crate::{harness, stdout};

pub fn run(args: &DemoArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let options = DemoOptions {
        source: args.source.clone(),
        hold_s: args.hold_s(),
        world_up: args.world_up,
        duration: args.duration,
        objects: args.objects,
        query_rate: args.query_rate,
    };
    let json = args.json;
    let mut on_line = |line: &str| {
        if json {
            Ok(())
        } else {
            stdout::print(line).map_err(|f| f.into_error().into())
        }
    };
    let finished =
        demo::run(&options, &config, &harness::bin_dir()?, &mut on_line).map_err(Failure::of)?;
    if json {
        stdout::print(&format!("{}\n", finished.report.json()))?;
    } else {
        stdout::print(&finished.report.table())?;
    }
    finished.stopped.runtime()
}
