//! `vref bench remote`: the arguments to vref_harness::bench_remote, the
//! report printed.

use vref_config::Config;
use vref_harness::bench_remote::{self, RemoteBenchOptions};

use crate::cli::BenchRemoteArgs;
use crate::failure::{Blame, Failure};
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
        bench_remote::run(&options, &config, &harness::bin_dir()?).map_err(harness::failure)?;
    let text = if args.json {
        format!("{}\n", finished.report.json(&options))
    } else {
        finished.report.table(&options)
    };
    stdout::print(&text)?;
    finished.stopped.runtime()
}
