use std::process::ExitCode;

/// A command's failure, sorted by whose fault it is (see the exit codes in
/// `main.rs`).
#[derive(Debug)]
pub enum Failure {
    /// The input was wrong: arguments, configuration, data.
    BadInput(anyhow::Error),
    /// Something broke while running.
    Runtime(anyhow::Error),
    /// The command did its work but the outcome it reports is not a
    /// success, with an exit code of its own (`vref query`: the matcher
    /// answered not_ready, stale or bad_request).
    Outcome(u8, anyhow::Error),
}

impl Failure {
    pub fn error(&self) -> &anyhow::Error {
        match self {
            Failure::BadInput(e) | Failure::Runtime(e) | Failure::Outcome(_, e) => e,
        }
    }

    pub fn into_error(self) -> anyhow::Error {
        match self {
            Failure::BadInput(e) | Failure::Runtime(e) | Failure::Outcome(_, e) => e,
        }
    }

    pub fn exit_code(&self) -> ExitCode {
        match self {
            Failure::BadInput(_) => ExitCode::from(2),
            Failure::Runtime(_) => ExitCode::from(1),
            Failure::Outcome(code, _) => ExitCode::from(*code),
        }
    }
}

/// Marks an error as the caller's (bad input) or the program's (runtime).
pub trait Blame<T> {
    fn bad_input(self) -> Result<T, Failure>;
    fn runtime(self) -> Result<T, Failure>;
}

impl<T, E: Into<anyhow::Error>> Blame<T> for Result<T, E> {
    fn bad_input(self) -> Result<T, Failure> {
        self.map_err(|e| Failure::BadInput(e.into()))
    }

    fn runtime(self) -> Result<T, Failure> {
        self.map_err(|e| Failure::Runtime(e.into()))
    }
}
