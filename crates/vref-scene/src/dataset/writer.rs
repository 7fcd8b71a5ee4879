use std::io::Write;

use super::DatasetError;
use super::record::PairRecord;
use crate::ScenePair;

/// Writes scene pairs as dataset lines. Output is a pure function of the
/// pairs (shortest round-trip float formatting), so equal scenes give
/// byte-identical files.
#[derive(Debug)]
pub struct DatasetWriter<W> {
    output: W,
}

impl<W: Write> DatasetWriter<W> {
    pub fn new(output: W) -> Self {
        Self { output }
    }

    pub fn write(&mut self, pair: &ScenePair) -> Result<(), DatasetError> {
        let wrap = |source| DatasetError::Write {
            name: pair.name.clone(),
            source,
        };
        serde_json::to_writer(&mut self.output, &PairRecord::from_pair(pair))
            // `From` keeps the kind of an underlying I/O error (a closed
            // pipe stays `BrokenPipe`); `io::Error::other` would hide it.
            .map_err(|e| wrap(std::io::Error::from(e)))?;
        self.output.write_all(b"\n").map_err(wrap)
    }

    /// Flushes and hands back the output.
    pub fn finish(mut self) -> Result<W, DatasetError> {
        self.output.flush().map_err(|source| DatasetError::Write {
            name: String::new(),
            source,
        })?;
        Ok(self.output)
    }
}
