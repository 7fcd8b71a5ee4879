//! `vref bench query` and its hidden echo server (`vref bench
//! echo-server`): the arguments to vref_harness::bench_query and
//! vref_harness::echo, the report printed.

use vref_config::Config;
use vref_harness::bench_query::{self, QueryBenchOptions};
use vref_harness::echo;
use vref_logging::exit::{Blame, Failure};

use crate::cli::{BenchQueryArgs, EchoServerArgs};
use crate::{harness, stdout};

pub fn query(args: &BenchQueryArgs) -> Result<(), Failure> {
    if args.objects < 2 {
        return Err(anyhow::anyhow!("--objects: at least 2")).bad_input();
    }
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let options = QueryBenchOptions {
        objects: args.objects,
        with_viewer: args.with_viewer,
        rate: args.rate,
        duration: args.duration,
        compare_idle: args.compare_idle,
        vref: harness::vref_exe()?,
    };
    let finished =
        bench_query::run(&options, &config, &harness::bin_dir()?).map_err(Failure::of)?;
    let reports = &finished.report;
    let text = if args.json {
        format!(
            "{}\n",
            reports.busy.json(&options, &config, reports.idle.as_ref())
        )
    } else {
        reports.busy.table(&options, &config, reports.idle.as_ref())
    };
    stdout::print(&text)?;
    finished.stopped.runtime()
}

/// `vref bench echo-server`: serves until SIGINT or SIGTERM.
pub fn echo_server(args: &EchoServerArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    echo::serve(&echo::echo_settings(&config.ipc))
        .map(|_| ())
        .runtime()
}
