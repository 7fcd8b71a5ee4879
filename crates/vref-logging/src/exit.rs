//! The one exit-code rule of every vref binary, so that scripts and
//! supervisors can tell "you asked wrong" from "it broke" whichever
//! binary they ran: 0 success (a service stopped on SIGINT/SIGTERM),
//! [`RUNTIME`] 1 a failure while running, [`BAD_INPUT`] 2 bad input
//! (arguments, configuration, data). clap's own argument errors exit 2
//! too. Only `vref query` adds codes, for an answer that is not a
//! success ([`Failure::Outcome`]).

use std::process::ExitCode;

/// A failure while running: a service died, nothing answered, I/O broke.
pub const RUNTIME: u8 = 1;
/// The input was wrong: arguments, configuration, data.
pub const BAD_INPUT: u8 = 2;

/// A binary's failure, sorted by whose fault it is.
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

/// An error that knows whose fault it is; each library's run error says
/// it, so that no binary decides for itself.
pub trait Fault {
    /// Whether the caller's input (arguments, configuration, data) was
    /// wrong, rather than something breaking while running.
    fn is_bad_input(&self) -> bool;
}

impl Failure {
    /// `error`, sorted by its own [`Fault`].
    pub fn of<E>(error: E) -> Self
    where
        E: Fault + std::error::Error + Send + Sync + 'static,
    {
        if error.is_bad_input() {
            Failure::BadInput(error.into())
        } else {
            Failure::Runtime(error.into())
        }
    }

    /// The same failure, its error with `context` in front.
    pub fn context(self, context: &'static str) -> Self {
        match self {
            Failure::BadInput(e) => Failure::BadInput(e.context(context)),
            Failure::Runtime(e) => Failure::Runtime(e.context(context)),
            Failure::Outcome(code, e) => Failure::Outcome(code, e.context(context)),
        }
    }

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

    pub fn code(&self) -> u8 {
        match self {
            Failure::BadInput(_) => BAD_INPUT,
            Failure::Runtime(_) => RUNTIME,
            Failure::Outcome(code, _) => *code,
        }
    }

    pub fn exit_code(&self) -> ExitCode {
        ExitCode::from(self.code())
    }
}

/// How a service's `main` ends: 0, or its failure logged with its causes
/// and its exit code.
pub fn finish<T>(result: Result<T, Failure>) -> ExitCode {
    match result {
        Ok(_) => ExitCode::SUCCESS,
        Err(failure) => {
            tracing::error!("{:#}", failure.error());
            failure.exit_code()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("wrong")]
    struct Wrong(bool);

    impl Fault for Wrong {
        fn is_bad_input(&self) -> bool {
            self.0
        }
    }

    #[test]
    fn an_error_sorts_itself_and_the_codes_are_the_rule() {
        assert_eq!(Failure::of(Wrong(true)).code(), 2);
        assert_eq!(Failure::of(Wrong(false)).code(), 1);
        let outcome = Failure::Outcome(4, anyhow::anyhow!("stale"));
        assert_eq!(outcome.code(), 4);
        let failed: Result<(), _> = Err(Wrong(false)).bad_input();
        assert!(failed.is_err_and(|f| f.code() == BAD_INPUT));
        let ros = Failure::of(Wrong(false)).context("vref-ros2");
        assert_eq!(format!("{:#}", ros.error()), "vref-ros2: wrong");
    }
}
