//! `vref up`: its arguments to vref_harness::up, its lines printed as
//! they come (a client reads the configuration path from the first).

use vref_config::Config;
use vref_harness::up::{self, UpOptions};
use vref_logging::exit::{Blame, Failure};

use crate::cli::UpArgs;
use crate::{harness, stdout};

pub fn run(args: &UpArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let options = UpOptions {
        objects: args.objects,
        duration: args.duration,
    };
    let mut on_line = |line: &str| stdout::print(line).map_err(|f| f.into_error().into());
    let finished =
        up::run(&options, &config, &harness::bin_dir()?, &mut on_line).map_err(Failure::of)?;
    finished.stopped.runtime()
}
