//! `vref bench remote`: the arguments to vref_harness::bench_remote, the
//! report printed.

use vref_config::Config;
use vref_harness::bench_remote::{self, RemoteBenchOptions};
use vref_logging::exit::{Blame, Failure};

use crate::cli::BenchRemoteArgs;
use crate::{harness, stdout};

pub fn remote(args: &BenchRemoteArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let options = RemoteBenchOptions {
        objects: args.objects,
        rate: args.rate,
        duration: args.duration,
        encoding: args.encoding,
    };
    let finished =
        bench_remote::run(&options, &config, &harness::bin_dir()?).map_err(Failure::of)?;
    let text = if args.json {
        format!("{}\n", finished.report.json(&options))
    } else {
        finished.report.table(&options)
    };
    stdout::print(&text)?;
    finished.stopped.runtime()
}
