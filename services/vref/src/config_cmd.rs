use vref_config::Config;

use crate::cli::ConfigCheckArgs;
use crate::failure::{Blame, Failure};

pub fn check(args: &ConfigCheckArgs) -> Result<(), Failure> {
    Config::from_file(&args.file).bad_input()?;
    crate::stdout::print(&format!("{}: ok\n", args.file.display()))
}
