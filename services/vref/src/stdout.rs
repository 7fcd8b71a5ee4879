use std::io::{ErrorKind, Write};
use vref_logging::exit::{Blame, Failure};

/// Writes `text` to stdout. A reader that went away (`vref eval | head`)
/// ends the output quietly, as other Unix tools do; any other write error
/// is a failure, never a panic.
pub fn print(text: &str) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == ErrorKind::BrokenPipe => Ok(()),
        result => result.runtime(),
    }
}
