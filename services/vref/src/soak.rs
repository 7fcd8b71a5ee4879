//! `vref soak`: its arguments to vref_harness::soak, the report printed.

use vref_config::Config;
use vref_harness::soak::{self, SoakOptions};
use vref_logging::exit::{Blame, Failure};

use crate::cli::SoakArgs;
use crate::{harness, stdout};

pub fn run(args: &SoakArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let options = SoakOptions {
        duration: args.duration,
        objects: args.objects,
        feed_rate: args.feed_rate,
        query_rate: args.query_rate,
        timeout: args.timeout(),
    };
    let finished = soak::run(&options, &config, &harness::bin_dir()?).map_err(Failure::of)?;
    if args.json {
        stdout::print(&format!("{}\n", finished.report.json()))?;
    } else {
        stdout::print(&finished.report.table())?;
    }
    finished.stopped.runtime()
}
