//! A progress bar on stderr for runs long enough to wonder about, drawn
//! only for a person at a terminal: piped or redirected stderr, as in
//! scripts and CI, gets nothing from it.

use std::fs::File;
use std::io::{IsTerminal, Read};
use std::path::Path;

use indicatif::{ProgressBar, ProgressFinish, ProgressStyle};

/// A bar counting the scenes of the dataset file at `dataset`: a bar with
/// an end if the file's scenes could be counted, else a running count.
/// It clears itself when dropped, also on an early error return.
pub fn scenes(dataset: &Path) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = match count_scenes(dataset) {
        Some(total) => ProgressBar::new(total).with_style(style(
            "{spinner} scene {pos}/{len} [{wide_bar}] {elapsed} (eta {eta})",
        )),
        None => ProgressBar::new_spinner().with_style(style("{spinner} scene {pos} {elapsed}")),
    };
    bar.with_finish(ProgressFinish::AndClear)
}

/// A bar counting `total` scenes that are generated, not read from a file.
pub fn generated(total: u64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    ProgressBar::new(total)
        .with_style(style(
            "{spinner} scene {pos}/{len} [{wide_bar}] {elapsed} (eta {eta})",
        ))
        .with_finish(ProgressFinish::AndClear)
}

fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar())
}

/// Non-blank lines of the file, as the dataset reader counts scenes (its
/// bad lines included); `None` if it cannot be read, which the reader will
/// then report properly.
fn count_scenes(path: &Path) -> Option<u64> {
    let mut file = File::open(path).ok()?;
    let mut buffer = vec![0u8; 1 << 16];
    let (mut lines, mut blank) = (0u64, true);
    loop {
        let read = match file.read(&mut buffer) {
            Ok(0) => break,
            Ok(read) => read,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(_) => return None,
        };
        for &byte in &buffer[..read] {
            if byte == b'\n' {
                lines += u64::from(!blank);
                blank = true;
            } else if !byte.is_ascii_whitespace() {
                blank = false;
            }
        }
    }
    Some(lines + u64::from(!blank))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::count_scenes;

    #[test]
    fn counts_non_blank_lines_as_the_reader_does() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("d.jsonl");
        for (text, expected) in [
            ("", 0),
            ("{}\n", 1),
            ("{}", 1),
            ("{}\n\n  \n{}\n{}", 3),
            ("\n\n", 0),
            ("{}\r\n{}\r\n", 2),
        ] {
            std::fs::write(&path, text).unwrap();
            assert_eq!(count_scenes(&path), Some(expected), "{text:?}");
        }
        assert_eq!(count_scenes(&dir.path().join("missing")), None);
    }
}
