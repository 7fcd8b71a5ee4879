//! `vref bench client`: the arguments to vref_harness::bench_client, the
//! report printed.

use vref_config::Config;
use vref_harness::bench_client::{self, ClientBenchOptions};
use vref_logging::exit::{Blame, Failure};

use crate::cli::BenchClientArgs;
use crate::stdout;

pub fn run(args: &BenchClientArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let options = ClientBenchOptions {
        rate: args.rate,
        duration: args.duration,
        ready_within: args.ready_within,
    };
    let report = bench_client::run(&options, &config.ipc).map_err(Failure::of)?;
    let text = if args.json {
        format!("{}\n", report.json(&options))
    } else {
        report.table(&options)
    };
    stdout::print(&text)
}
