//! Child service processes under their own iceoryx2 root path and prefix,
//! for commands that run the whole system themselves (`vref demo`,
//! `vref bench query`, `vref soak`).

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, anyhow, bail};
use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;
use vref_config::Config;

/// How long a service may take to stop after SIGTERM.
const STOP_WITHIN: Duration = Duration::from_secs(10);
/// The matcher and the two feeds.
pub const SERVICES: [&str; 3] = ["vref-matcher", "vref-perception-feed", "vref-gesture-feed"];

/// A binary installed beside this one.
pub fn sibling(name: &str) -> anyhow::Result<PathBuf> {
    let exe = std::env::current_exe().context("locating vref")?;
    let path = exe.with_file_name(name);
    if !path.exists() {
        bail!(
            "{} not found beside {}: build every service first (cargo build --release)",
            name,
            exe.display()
        );
    }
    Ok(path)
}

/// Everything a command needs to run the system on its own: the service
/// binaries, a temporary directory (logs, iceoryx2 root path, the
/// configuration file) and the isolated configuration written there.
pub struct Isolation {
    pub binaries: Vec<PathBuf>,
    pub dir: tempfile::TempDir,
    pub config: Config,
    pub config_path: PathBuf,
}

/// Keeps the run's directory (the services' logs) when the run failed,
/// so that the paths its error names still exist; removes it otherwise.
pub fn keep_logs_if(failed: bool, dir: tempfile::TempDir) {
    if failed {
        let path = dir.keep();
        tracing::warn!("the services' logs are kept in {}", path.display());
    }
}

/// Finds the service binaries and isolates `config` in a new directory
/// `vref-<name>-*` with iceoryx2 prefix `<tag><pid>_`: the services
/// started never meet, or disturb, services already running here.
pub fn prepare(config: &Config, name: &str, tag: &str) -> anyhow::Result<Isolation> {
    let binaries = SERVICES
        .iter()
        .map(|service| sibling(service))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let dir = tempfile::Builder::new()
        .prefix(&format!("vref-{name}-"))
        .tempdir()?;
    let config = isolated(config, dir.path(), tag)?;
    let config_path = write_config(&config, dir.path())?;
    Ok(Isolation {
        binaries,
        dir,
        config,
        config_path,
    })
}

/// `config` with its own root path in `dir` and a prefix of its own, so
/// that the services started never meet, or disturb, services already
/// running on this machine. `tag` starts the prefix.
fn isolated(config: &Config, dir: &Path, tag: &str) -> anyhow::Result<Config> {
    let root = dir.join("iceoryx2");
    std::fs::create_dir_all(&root)?;
    let mut own = config.clone();
    own.ipc.root_path = Some(root);
    own.ipc.prefix = format!("{tag}{}_", std::process::id());
    Ok(own)
}

/// Writes `config` into `dir` for the children to read.
fn write_config(config: &Config, dir: &Path) -> anyhow::Result<PathBuf> {
    let path = dir.join("vref.toml");
    let text = toml::to_string(config).context("writing the configuration")?;
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}

/// Service processes; stopped with SIGTERM, killed if they hang. Each
/// logs into `<name>.log` in the log directory.
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
    /// `--config`, the feeds with `--objects` if given.
    pub fn start_system(
        binaries: &[PathBuf],
        config: &Path,
        objects: Option<usize>,
        logs: &Path,
    ) -> anyhow::Result<Self> {
        let feed_args = match objects {
            Some(n) => vec!["--objects".to_owned(), n.to_string()],
            None => Vec::new(),
        };
        Self::start_system_with(binaries, config, &feed_args, logs)
    }

    /// The matcher and both feeds from `binaries` (as [`SERVICES`]) with
    /// `--config`, the feeds with `feed_args` besides.
    pub fn start_system_with(
        binaries: &[PathBuf],
        config: &Path,
        feed_args: &[String],
        logs: &Path,
    ) -> anyhow::Result<Self> {
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
    ) -> anyhow::Result<()> {
        for binary in binaries {
            let name = binary
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            if !chosen(&name) {
                continue;
            }
            let mut command = Command::new(binary);
            command.arg("--config").arg(config);
            if name.ends_with("feed") {
                command.args(feed_args);
            }
            self.spawn(&name, command)?;
        }
        Ok(())
    }

    /// Stops service `name` with SIGTERM, as [`Services::stop`] does.
    pub fn stop_one(&mut self, name: &str) -> anyhow::Result<()> {
        let Some(index) = self.children.iter().position(|(n, _)| n == name) else {
            bail!("no service {name}");
        };
        let (name, mut child) = self.children.remove(index);
        stop_child(&name, &mut child).map_err(|problem| anyhow!("{problem}"))
    }

    /// Starts `command` as the service `name`.
    pub fn spawn(&mut self, name: &str, mut command: Command) -> anyhow::Result<()> {
        let log = std::fs::File::create(self.logs.join(format!("{name}.log")))?;
        let child = command
            .stdin(Stdio::null())
            .stdout(log.try_clone()?)
            .stderr(log)
            .spawn()
            .with_context(|| format!("starting {name}"))?;
        tracing::info!(service = %name, pid = child.id(), "started");
        self.children.push((name.to_owned(), child));
        Ok(())
    }

    /// An error naming each service that has exited on its own, how, and
    /// the last line of its log (where a service says why it stopped, e.g.
    /// a configuration it refused); `Ok` while all of them run.
    pub fn ensure_running(&mut self) -> anyhow::Result<()> {
        let mut exited = Vec::new();
        for (name, child) in &mut self.children {
            if let Ok(Some(status)) = child.try_wait() {
                exited.push((name.clone(), status));
            }
        }
        if exited.is_empty() {
            return Ok(());
        }
        let reports: Vec<String> = exited
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
        Err(anyhow!(
            "{} (logs in {})",
            reports.join("; "),
            self.logs.display()
        ))
    }

    /// What service `name` logged so far.
    pub fn log(&self, name: &str) -> String {
        std::fs::read_to_string(self.logs.join(format!("{name}.log"))).unwrap_or_default()
    }

    /// SIGTERM to each, then waits; a service that does not stop in time
    /// is killed and reported.
    pub fn stop(&mut self) -> anyhow::Result<()> {
        let problems: Vec<String> = self
            .children
            .drain(..)
            .filter_map(|(name, mut child)| stop_child(&name, &mut child).err())
            .collect();
        if problems.is_empty() {
            Ok(())
        } else {
            Err(anyhow!(
                "{} (logs in {})",
                problems.join("; "),
                self.logs.display()
            ))
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
