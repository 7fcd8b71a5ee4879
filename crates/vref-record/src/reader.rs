use std::io::{ErrorKind, Read};

use crate::{Frame, MAGIC, MAGIC_V1, MAX_FRAME_BYTES, RecordError};

/// Reads the frames of a recording in order.
#[derive(Debug)]
pub struct RecordingReader<R: Read> {
    input: R,
    frame: u64,
    /// Bytes of the magic and the frames read so far.
    offset: u64,
    done: bool,
    /// A `VREFREC1` file, whose snapshots have no up vector.
    v1: bool,
}

impl<R: Read> RecordingReader<R> {
    /// Checks the magic.
    pub fn new(mut input: R) -> Result<Self, RecordError> {
        let mut magic = [0u8; 8];
        input
            .read_exact(&mut magic)
            .map_err(|source| match source.kind() {
                ErrorKind::UnexpectedEof => RecordError::BadMagic,
                _ => RecordError::Io { frame: 0, source },
            })?;
        let v1 = match &magic {
            m if m == MAGIC => false,
            m if m == MAGIC_V1 => true,
            _ => return Err(RecordError::BadMagic),
        };
        Ok(Self {
            input,
            frame: 0,
            offset: magic.len() as u64,
            done: false,
            v1,
        })
    }

    fn read_frame(&mut self) -> Result<Option<Frame>, RecordError> {
        let frame = self.frame;
        let mut length = [0u8; 4];
        match read_full(&mut self.input, &mut length) {
            Ok(0) => return Ok(None),
            Ok(4) => {}
            Ok(_) => return Err(RecordError::Truncated { frame }),
            Err(source) => return Err(RecordError::Io { frame, source }),
        }
        let length = u32::from_le_bytes(length);
        if length > MAX_FRAME_BYTES {
            return Err(RecordError::FrameTooLarge {
                frame,
                length,
                limit: MAX_FRAME_BYTES,
            });
        }
        let mut bytes = vec![0u8; length as usize];
        match read_full(&mut self.input, &mut bytes) {
            Ok(n) if n == bytes.len() => {}
            Ok(_) => return Err(RecordError::Truncated { frame }),
            Err(source) => return Err(RecordError::Io { frame, source }),
        }
        let decoded = if self.v1 {
            decode::<crate::frame::v1::Frame>(&bytes, frame).map(|(f, used)| (f.into(), used))
        } else {
            decode::<Frame>(&bytes, frame)
        };
        let (decoded, used): (Frame, usize) = decoded?;
        if used != bytes.len() {
            return Err(RecordError::Decode {
                frame,
                message: format!("{} trailing bytes", bytes.len() - used),
            });
        }
        self.frame += 1;
        self.offset += 4 + u64::from(length);
        Ok(Some(decoded))
    }

    /// Bytes of the magic and the whole frames read so far: where a file
    /// cut short stops being readable.
    pub fn offset(&self) -> u64 {
        self.offset
    }
}

fn decode<T: serde::de::DeserializeOwned>(
    bytes: &[u8],
    frame: u64,
) -> Result<(T, usize), RecordError> {
    bincode::serde::decode_from_slice::<T, _>(bytes, bincode::config::standard()).map_err(|e| {
        RecordError::Decode {
            frame,
            message: e.to_string(),
        }
    })
}

/// Reads until `buf` is full or the input ends; returns the bytes read.
fn read_full(input: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buf.len() {
        match input.read(&mut buf[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(filled)
}

impl<R: Read> Iterator for RecordingReader<R> {
    type Item = Result<Frame, RecordError>;

    /// Yields frames until the end; the first error ends the stream.
    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let item = self.read_frame().transpose();
        if !matches!(item, Some(Ok(_))) {
            self.done = true;
        }
        item
    }
}
