use vref_config::Config;
use vref_logging::exit::{Blame, Failure};

use crate::cli::ConfigCheckArgs;

pub fn check(args: &ConfigCheckArgs) -> Result<(), Failure> {
    Config::from_file(&args.file).bad_input()?;
    crate::stdout::print(&format!("{}: ok\n", args.file.display()))
}
