//! Reading a recording as far as it is whole: a recorder killed or a disk
//! filled leaves a file cut at some byte, and everything before the cut
//! is still worth replaying.

use std::fmt;

use crate::{Frame, MAGIC, MAGIC_V1, MCAP_MAGIC, RecordError, RecordingReader};

/// The frames of a recording, and where it stopped if it was cut short.
#[derive(Debug)]
pub struct Recording {
    pub frames: Vec<Frame>,
    pub cut: Option<Cut>,
}

/// Where a recording cut short stops being readable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cut {
    /// Bytes before the first incomplete record (an MCAP record or chunk,
    /// or a frame of vref's own format): everything before was read.
    pub readable: u64,
    /// The file's length.
    pub length: u64,
    /// The first frame not read (frames are counted from 0).
    pub frame: u64,
}

impl fmt::Display for Cut {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the file is cut short: {} frames read from its first {} of {} bytes, the rest is an incomplete record",
            self.frame, self.readable, self.length
        )
    }
}

/// Every frame of a recording in either format, up to the last complete
/// MCAP chunk (or frame of vref's own format) if the file was cut short.
/// Damage other than a cut (a bad message inside a complete chunk) is
/// still an error: it is not a recording stopped early but a wrong one.
pub fn read_recording(bytes: &[u8]) -> Result<Recording, RecordError> {
    if bytes.is_empty() {
        return Err(RecordError::Empty);
    }
    let length = bytes.len() as u64;
    if bytes.starts_with(MCAP_MAGIC) {
        return read_mcap(bytes);
    }
    // A file cut inside its magic has nothing to read but is still the
    // recording it was meant to be.
    if bytes.len() < MAGIC.len()
        && [&MCAP_MAGIC[..], MAGIC, MAGIC_V1]
            .iter()
            .any(|magic| magic.starts_with(bytes))
    {
        return Ok(Recording {
            frames: Vec::new(),
            cut: Some(Cut {
                readable: 0,
                length,
                frame: 0,
            }),
        });
    }
    let mut reader = RecordingReader::new(bytes)?;
    let mut frames = Vec::new();
    for frame in reader.by_ref() {
        match frame {
            Ok(frame) => frames.push(frame),
            Err(RecordError::Truncated { frame }) => {
                let cut = Cut {
                    readable: reader.offset(),
                    length,
                    frame,
                };
                return Ok(Recording {
                    frames,
                    cut: Some(cut),
                });
            }
            Err(e) => return Err(e),
        }
    }
    Ok(Recording { frames, cut: None })
}

/// MCAP's framing: an opcode byte and a little-endian u64 body length.
const RECORD_HEAD: usize = 9;
const OP_FOOTER: u8 = 0x02;

fn read_mcap(bytes: &[u8]) -> Result<Recording, RecordError> {
    let Some(readable) = whole_records(bytes) else {
        let frames = crate::mcap_frames(bytes)?;
        return Ok(Recording { frames, cut: None });
    };
    let frames = crate::mcap_file::mcap_frames_with(&bytes[..readable], true)?;
    let cut = Cut {
        readable: readable as u64,
        length: bytes.len() as u64,
        frame: frames.len() as u64,
    };
    Ok(Recording {
        frames,
        cut: Some(cut),
    })
}

/// `None` for a complete file (its footer and closing magic present),
/// else the length of its whole records: where a cut file stops being
/// readable. Only the framing is read here; the records themselves are
/// the MCAP reader's.
fn whole_records(bytes: &[u8]) -> Option<usize> {
    let mut at = MCAP_MAGIC.len();
    loop {
        let rest = &bytes[at..];
        let Some((head, body)) = rest.split_at_checked(RECORD_HEAD) else {
            return Some(at);
        };
        let mut len = [0u8; 8];
        len.copy_from_slice(&head[1..]);
        let len = u64::from_le_bytes(len);
        if len > body.len() as u64 {
            return Some(at);
        }
        let end = at + RECORD_HEAD + len as usize;
        if head[0] == OP_FOOTER {
            return if bytes[end..].starts_with(MCAP_MAGIC) {
                None
            } else {
                Some(end)
            };
        }
        at = end;
    }
}
