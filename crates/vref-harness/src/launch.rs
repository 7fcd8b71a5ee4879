//! The one process launcher: child service processes under their own
//! iceoryx2 root path and prefix, for runs of the whole system (`vref
//! demo`, `vref soak`, `vref bench query`, `vref bench remote`). Each
//! logs into `<name>.log` in the run's directory; each is stopped with
//! SIGTERM and killed if it has not exited within [`STOP_WITHIN`].

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;
use vref_config::Config;

/// How long a service may take to stop after SIGTERM.
pub const STOP_WITHIN: Duration = Duration::from_secs(10);
/// The matcher and the two feeds.
pub const SERVICES: [&str; 3] = ["vref-matcher", "vref-perception-feed", "vref-gesture-feed"];
/// The feeds, which take the feed arguments.
pub const FEEDS: [&str; 2] = ["vref-perception-feed", "vref-gesture-feed"];

/// Why services could not be prepared, started, kept or stopped.
#[derive(Debug, thiserror::Error)]
pub enum LaunchError {
    #[error("{name} not found in {}: build every service first (cargo build --release)", dir.display())]
    NotFound { name: String, dir: PathBuf },
    #[error("{what}: {source}")]
    Io {
        what: String,
        source: std::io::Error,
    },
    #[error("writing the configuration: {0}")]
    Config(#[from] toml::ser::Error),
    #[error("starting {name}: {source}")]
    Spawn {
        name: String,
        source: std::io::Error,
    },
    /// Services that exited on their own, each with how and the last line
    /// of its log.
    #[error("{} (logs in {})", reports.join("; "), logs.display())]
    Exited { reports: Vec<String>, logs: PathBuf },
    /// Services that did not stop cleanly.
    #[error("{} (logs in {})", problems.join("; "), logs.display())]
    Stop {
        problems: Vec<String>,
        logs: PathBuf,
    },
    #[error("no service {0}")]
    NoService(String),
}

fn io(what: impl Into<String>) -> impl FnOnce(std::io::Error) -> LaunchError {
    let what = what.into();
    move |source| LaunchError::Io { what, source }
}

/// Binary `name` in `dir` (where the service binaries are installed).
pub fn binary(dir: &Path, name: &str) -> Result<PathBuf, LaunchError> {
    let path = dir.join(name);
    if path.exists() {
        Ok(path)
    } else {
        Err(LaunchError::NotFound {
            name: name.to_owned(),
            dir: dir.to_owned(),
        })
    }
}

/// Everything a run of the whole system needs: the service binaries (as
/// [`SERVICES`]), a temporary directory (logs, iceoryx2 root path, the
/// configuration file) and the isolated configuration written there.
#[derive(Debug)]
pub struct Isolation {
    pub binaries: Vec<PathBuf>,
    pub dir: tempfile::TempDir,
    pub config: Config,
    pub config_path: PathBuf,
}

/// What a run's body works with: the isolated configuration, its file
/// and the run's directory (the services' logs), beside the services.
#[derive(Debug)]
pub struct Run<'a> {
    pub config: &'a Config,
    pub config_path: &'a Path,
    pub binaries: &'a [PathBuf],
    pub dir: &'a Path,
}

impl Isolation {
    /// The one skeleton of every run: the matcher and both feeds started
    /// (the feeds with `feed_args`), `body` run on them, the services
    /// stopped, `after_stop` given what they left (their logs), and the
    /// run's directory kept where the body or the stop failed.
    pub fn run_system<R>(
        self,
        feed_args: &[String],
        body: impl FnOnce(&Run<'_>, &mut Services) -> Result<R, crate::RunError>,
        after_stop: impl FnOnce(&mut R, &Services),
    ) -> Result<crate::Finished<R>, crate::RunError> {
        let Isolation {
            binaries,
            dir,
            config,
            config_path,
        } = self;
        let mut services = Services::start_system(&binaries, &config_path, feed_args, dir.path())?;
        let run = Run {
            config: &config,
            config_path: &config_path,
            binaries: &binaries,
            dir: dir.path(),
        };
        let mut outcome = body(&run, &mut services);
        let stopped = services.stop();
        if let Ok(report) = &mut outcome {
            after_stop(report, &services);
        }
        keep_logs_if(outcome.is_err() || stopped.is_err(), dir);
        Ok(crate::Finished {
            report: outcome?,
            stopped,
        })
    }
}

/// Keeps the run's directory (the services' logs) when the run failed,
/// so that the paths its error names still exist, and logs where (and
/// returns it); removes it otherwise.
pub fn keep_logs_if(failed: bool, dir: tempfile::TempDir) -> Option<PathBuf> {
    failed.then(|| {
        let path = dir.keep();
        tracing::warn!("the services' logs are kept in {}", path.display());
        path
    })
}

/// Finds the service binaries in `bin_dir` and isolates `config` in a new
/// directory `vref-<name>-*` with iceoryx2 prefix `<tag><pid>_`: the
/// services started never meet, or disturb, services already running.
pub fn prepare(
    config: &Config,
    bin_dir: &Path,
    name: &str,
    tag: &str,
) -> Result<Isolation, LaunchError> {
    let binaries = SERVICES
        .iter()
        .map(|service| binary(bin_dir, service))
        .collect::<Result<Vec<_>, _>>()?;
    let dir = tempfile::Builder::new()
        .prefix(&format!("vref-{name}-"))
        .tempdir()
        .map_err(io("creating the run's directory"))?;
    let config = isolated(config, dir.path(), tag)?;
    let config_path = write_config(&config, dir.path())?;
    Ok(Isolation {
        binaries,
        dir,
        config,
        config_path,
    })
}

/// `config` with its own root path in `dir` and a prefix of its own.
fn isolated(config: &Config, dir: &Path, tag: &str) -> Result<Config, LaunchError> {
    let root = dir.join("iceoryx2");
    std::fs::create_dir_all(&root).map_err(io(format!("creating {}", root.display())))?;
    let mut own = config.clone();
    own.ipc.root_path = Some(root);
    own.ipc.prefix = format!("{tag}{}_", std::process::id());
    Ok(own)
}

/// Writes `config` into `dir` for the children to read.
fn write_config(config: &Config, dir: &Path) -> Result<PathBuf, LaunchError> {
    write_config_as(config, dir, "vref.toml")
}

/// Writes `config` into `dir` as `file_name` for the children to read.
pub fn write_config_as(
    config: &Config,
    dir: &Path,
    file_name: &str,
) -> Result<PathBuf, LaunchError> {
    let path = dir.join(file_name);
    let text = toml::to_string(config)?;
    std::fs::write(&path, text).map_err(io(format!("writing {}", path.display())))?;
    Ok(path)
}

/// Service processes; stopped with SIGTERM, killed if they hang (also
/// when dropped). Each logs into `<name>.log` in the log directory.
#[derive(Debug)]
pub struct Services {
    children: Vec<(String, Child)>,
    logs: PathBuf,
}

impl Services {
    pub fn new(logs: &Path) -> Self {
        Services {
            children: Vec::new(),
            logs: logs.to_owned(),
        }
    }

    /// The matcher and both feeds from `binaries` (as [`SERVICES`]) with
    /// `--config`, the feeds with `feed_args` besides.
    pub fn start_system(
        binaries: &[PathBuf],
        config: &Path,
        feed_args: &[String],
        logs: &Path,
    ) -> Result<Self, LaunchError> {
        let mut services = Services::new(logs);
        services.start_some(binaries, config, feed_args, |_| true)?;
        Ok(services)
    }

    /// Starts those of `binaries` whose name `chosen` takes, as
    /// [`Services::start_system`] would.
    pub fn start_some(
        &mut self,
        binaries: &[PathBuf],
        config: &Path,
        feed_args: &[String],
        chosen: impl Fn(&str) -> bool,
    ) -> Result<(), LaunchError> {
        for binary in binaries {
            let name = binary
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            if !chosen(&name) {
                continue;
            }
            let mut command = Command::new(binary);
            command.arg("--config").arg(config);
            if FEEDS.contains(&name.as_str()) {
                command.args(feed_args);
            }
            self.spawn(&name, command)?;
        }
        Ok(())
    }

    /// Starts `program` with `args` as the service `name`.
    pub fn start(
        &mut self,
        name: &str,
        program: &Path,
        args: &[&std::ffi::OsStr],
    ) -> Result<(), LaunchError> {
        let mut command = Command::new(program);
        command.args(args);
        self.spawn(name, command)
    }

    /// Stops service `name` with SIGTERM, as [`Services::stop`] does.
    pub fn stop_one(&mut self, name: &str) -> Result<(), LaunchError> {
        let Some(index) = self.children.iter().position(|(n, _)| n == name) else {
            return Err(LaunchError::NoService(name.to_owned()));
        };
        let (name, mut child) = self.children.remove(index);
        stop_child(&name, &mut child).map_err(|problem| LaunchError::Stop {
            problems: vec![problem],
            logs: self.logs.clone(),
        })
    }

    /// Starts `command` as the service `name`, its output into its log.
    pub fn spawn(&mut self, name: &str, mut command: Command) -> Result<(), LaunchError> {
        let path = self.logs.join(format!("{name}.log"));
        let log =
            std::fs::File::create(&path).map_err(io(format!("creating {}", path.display())))?;
        let out = log
            .try_clone()
            .map_err(io(format!("opening {}", path.display())))?;
        let child = command
            .stdin(Stdio::null())
            .stdout(out)
            .stderr(log)
            .spawn()
            .map_err(|source| LaunchError::Spawn {
                name: name.to_owned(),
                source,
            })?;
        tracing::info!(service = %name, pid = child.id(), "started");
        self.children.push((name.to_owned(), child));
        Ok(())
    }

    /// An error naming each service that has exited on its own, how, and
    /// the last line of its log (where a service says why it stopped, e.g.
    /// a configuration it refused); `Ok` while all of them run.
    pub fn ensure_running(&mut self) -> Result<(), LaunchError> {
        let mut exited = Vec::new();
        for (name, child) in &mut self.children {
            if let Ok(Some(status)) = child.try_wait() {
                exited.push((name.clone(), status));
            }
        }
        if exited.is_empty() {
            return Ok(());
        }
        let reports = exited
            .iter()
            .map(|(name, status)| {
                let log = self.log(name);
                let last = log.lines().rev().find(|l| !l.trim().is_empty());
                match last {
                    Some(line) => format!("{name} exited with {status}: {}", line.trim()),
                    None => format!("{name} exited with {status}"),
                }
            })
            .collect();
        Err(LaunchError::Exited {
            reports,
            logs: self.logs.clone(),
        })
    }

    /// The process id of service `name`, while it is one of these.
    pub fn pid(&self, name: &str) -> Option<u32> {
        self.children
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, c)| c.id())
    }

    /// Service `name`'s process, to signal it or ask whether it exited.
    pub fn child(&mut self, name: &str) -> Option<&mut Child> {
        self.children
            .iter_mut()
            .find(|(n, _)| n == name)
            .map(|(_, c)| c)
    }

    /// Service `name`'s process, no longer one of these: the caller waits
    /// for it (and reaps it) itself.
    pub fn remove(&mut self, name: &str) -> Option<Child> {
        let index = self.children.iter().position(|(n, _)| n == name)?;
        Some(self.children.remove(index).1)
    }

    /// SIGKILL to each, then reaps them: for a run that is abandoned, where
    /// an orderly stop would only wait.
    pub fn kill_all(&mut self) {
        for (_, mut child) in self.children.drain(..) {
            child.kill().ok();
            child.wait().ok();
        }
    }

    /// What service `name` logged so far.
    pub fn log(&self, name: &str) -> String {
        std::fs::read_to_string(self.logs.join(format!("{name}.log"))).unwrap_or_default()
    }

    /// SIGTERM to each, then waits; a service that does not stop in time
    /// is killed and reported.
    pub fn stop(&mut self) -> Result<(), LaunchError> {
        let problems: Vec<String> = self
            .children
            .drain(..)
            .filter_map(|(name, mut child)| stop_child(&name, &mut child).err())
            .collect();
        if problems.is_empty() {
            Ok(())
        } else {
            Err(LaunchError::Stop {
                problems,
                logs: self.logs.clone(),
            })
        }
    }
}

/// SIGTERM, then a bounded wait; killed if it hangs. The problem, if any,
/// in words.
fn stop_child(name: &str, child: &mut Child) -> Result<(), String> {
    let pid = Pid::from_raw(i32::try_from(child.id()).unwrap_or(i32::MAX));
    kill(pid, Signal::SIGTERM).ok();
    let deadline = Instant::now() + STOP_WITHIN;
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(20)),
            _ => break None,
        }
    };
    match status {
        Some(s) if s.success() => {
            tracing::info!(service = %name, "stopped");
            Ok(())
        }
        Some(s) => Err(format!("{name} exited with {s}")),
        None => {
            child.kill().ok();
            child.wait().ok();
            Err(format!(
                "{name} did not stop within {STOP_WITHIN:?} and was killed"
            ))
        }
    }
}

impl Drop for Services {
    fn drop(&mut self) {
        if !self.children.is_empty() {
            self.stop().ok();
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    #[test]
    fn a_missing_binary_is_named_with_its_folder() {
        let dir = tempfile::tempdir().unwrap();
        let e = prepare(&Config::default(), dir.path(), "t", "vt").unwrap_err();
        assert!(e.to_string().contains("vref-matcher not found in"), "{e}");
    }

    #[test]
    fn a_service_can_be_handed_over_and_the_rest_killed_at_once() {
        let dir = tempfile::tempdir().unwrap();
        let mut services = Services::new(dir.path());
        for name in ["kept", "handed"] {
            let mut sleeper = Command::new("sleep");
            sleeper.arg("30");
            services.spawn(name, sleeper).unwrap();
        }
        assert!(services.child("nobody").is_none());
        let kept = services.child("kept").unwrap().id();
        assert_eq!(services.pid("kept"), Some(kept));
        let mut handed = services.remove("handed").unwrap();
        assert!(services.pid("handed").is_none());
        services.kill_all();
        assert!(services.pid("kept").is_none());
        // Reaped: no process of that id is left to signal.
        let gone = kill(Pid::from_raw(kept as i32), None);
        assert!(gone.is_err(), "{kept} is still there");
        assert_eq!(handed.try_wait().unwrap(), None, "the handed-over one runs");
        handed.kill().unwrap();
        handed.wait().unwrap();
    }

    #[test]
    fn a_service_that_exits_is_reported_with_its_last_log_line_and_one_that_hangs_is_killed() {
        let dir = tempfile::tempdir().unwrap();
        let mut services = Services::new(dir.path());
        let mut quits = Command::new("sh");
        quits.args(["-c", "echo refused this; exit 3"]);
        services.spawn("quits", quits).unwrap();
        let mut runs = Command::new("sleep");
        runs.arg("30");
        services.spawn("runs", runs).unwrap();
        let deadline = Instant::now() + Duration::from_secs(10);
        let e = loop {
            match services.ensure_running() {
                Err(e) => break e,
                Ok(()) if Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_millis(20))
                }
                Ok(()) => panic!("the quitting service never exited"),
            }
        };
        assert!(
            e.to_string()
                .contains("quits exited with exit status: 3: refused this"),
            "{e}"
        );
        // sleep stops on SIGTERM (killed by it: not a success).
        let stopped = services.stop().unwrap_err().to_string();
        assert!(stopped.contains("runs exited with signal"), "{stopped}");
    }
}
