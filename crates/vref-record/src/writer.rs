use std::io::Write;

use crate::{Frame, MAGIC, RecordError};

/// Appends frames to a recording.
#[derive(Debug)]
pub struct RecordingWriter<W: Write> {
    output: W,
    frames: u64,
    buffer: Vec<u8>,
}

impl<W: Write> RecordingWriter<W> {
    /// Writes the magic; frames follow.
    pub fn new(mut output: W) -> Result<Self, RecordError> {
        output
            .write_all(MAGIC)
            .map_err(|source| RecordError::Io { frame: 0, source })?;
        Ok(Self {
            output,
            frames: 0,
            buffer: Vec::new(),
        })
    }

    pub fn write(&mut self, frame: &Frame) -> Result<(), RecordError> {
        let index = self.frames;
        self.buffer.clear();
        bincode::serde::encode_into_std_write(frame, &mut self.buffer, bincode::config::standard())
            .map_err(|e| RecordError::Encode {
                frame: index,
                message: e.to_string(),
            })?;
        let length = u32::try_from(self.buffer.len()).map_err(|_| RecordError::Encode {
            frame: index,
            message: format!("{} bytes do not fit a frame", self.buffer.len()),
        })?;
        let io = |source| RecordError::Io {
            frame: index,
            source,
        };
        self.output.write_all(&length.to_le_bytes()).map_err(io)?;
        self.output.write_all(&self.buffer).map_err(io)?;
        self.frames += 1;
        Ok(())
    }

    /// Frames written so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Flushes and hands back the output.
    pub fn finish(mut self) -> Result<W, RecordError> {
        self.output.flush().map_err(|source| RecordError::Io {
            frame: self.frames,
            source,
        })?;
        Ok(self.output)
    }
}
