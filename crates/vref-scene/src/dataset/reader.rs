use std::fs::File;
use std::io::{BufRead, BufReader, ErrorKind, Read};
use std::path::Path;

use super::DatasetError;
use super::record::{JsonObject, PairRecord};
use crate::{Limits, ScenePair};

/// Longest line accepted; a scene of 256 objects with 512-float features
/// stays well below it, and a runaway file cannot exhaust memory.
const MAX_LINE_BYTES: usize = 64 * 1024 * 1024;

/// Streams scene pairs from a dataset file, one line at a time. Blank lines
/// are skipped but still counted, so line numbers match an editor's.
#[derive(Debug)]
pub struct DatasetReader<R> {
    input: R,
    limits: Limits,
    line: usize,
    buffer: Vec<u8>,
    failed: bool,
}

impl<R: BufRead> DatasetReader<R> {
    pub fn new(input: R, limits: Limits) -> Self {
        Self {
            input,
            limits,
            line: 0,
            buffer: Vec::new(),
            failed: false,
        }
    }

    /// Reads the next non-blank line into the buffer; `false` at the end.
    fn next_line(&mut self) -> Result<bool, DatasetError> {
        loop {
            self.buffer.clear();
            self.line += 1;
            let line = self.line;
            let mut bounded = Read::take(&mut self.input, MAX_LINE_BYTES as u64 + 1);
            let read = bounded
                .read_until(b'\n', &mut self.buffer)
                .map_err(|source| DatasetError::Io { line, source })?;
            if read == 0 {
                return Ok(false);
            }
            // At most MAX_LINE_BYTES + 1 bytes were read: a line of exactly
            // the limit plus its newline fits; anything longer does not.
            let ends_line = self.buffer.last() == Some(&b'\n');
            if self.buffer.len() > MAX_LINE_BYTES && !ends_line {
                self.buffer = Vec::new();
                self.skip_rest_of_line(line)?;
                return Err(DatasetError::LineTooLong {
                    line,
                    limit: MAX_LINE_BYTES,
                });
            }
            if !self.buffer.iter().all(u8::is_ascii_whitespace) {
                return Ok(true);
            }
        }
    }

    /// Discards input up to and including the next newline (or the end),
    /// without buffering it, so the next read starts on the next line.
    fn skip_rest_of_line(&mut self, line: usize) -> Result<(), DatasetError> {
        loop {
            let available = match self.input.fill_buf() {
                Ok(available) => available,
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                Err(source) => return Err(DatasetError::Io { line, source }),
            };
            if available.is_empty() {
                return Ok(());
            }
            let (used, done) = match available.iter().position(|&b| b == b'\n') {
                Some(end) => (end + 1, true),
                None => (available.len(), false),
            };
            self.input.consume(used);
            if done {
                return Ok(());
            }
        }
    }

    fn parse(&self) -> Result<ScenePair, DatasetError> {
        let line = self.line;
        let mut json = serde_json::Deserializer::from_slice(&self.buffer);
        let JsonObject(record): JsonObject<PairRecord> =
            serde_path_to_error::deserialize(&mut json).map_err(|e| DatasetError::Syntax {
                line,
                field: e.path().to_string(),
                message: e.inner().to_string(),
            })?;
        json.end().map_err(|e| DatasetError::Syntax {
            line,
            field: ".".to_owned(),
            message: e.to_string(),
        })?;
        let name = record.name.clone();
        record
            .into_pair(&self.limits)
            .map_err(|source| DatasetError::Invalid { line, name, source })
    }
}

impl<R: BufRead> Iterator for DatasetReader<R> {
    type Item = Result<ScenePair, DatasetError>;

    /// Yields each scene pair, or the error of a bad line. After an I/O
    /// error the stream ends; after a bad line (including one longer than
    /// the limit) it goes on with the next.
    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        match self.next_line() {
            Ok(true) => Some(self.parse()),
            Ok(false) => None,
            Err(e) => {
                // An over-long line has been skipped; any other failure here
                // is an I/O error, after which the input cannot be trusted.
                if !matches!(e, DatasetError::LineTooLong { .. }) {
                    self.failed = true;
                }
                Some(Err(e))
            }
        }
    }
}

/// Reads a whole dataset file, stopping at the first bad line.
pub fn read_dataset_file(path: &Path, limits: Limits) -> Result<Vec<ScenePair>, DatasetError> {
    let file = File::open(path).map_err(|source| DatasetError::Open {
        path: path.to_owned(),
        source,
    })?;
    DatasetReader::new(BufReader::new(file), limits).collect()
}
