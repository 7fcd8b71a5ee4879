/// Why a recording could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("I/O error at frame {frame}")]
    Io {
        frame: u64,
        #[source]
        source: std::io::Error,
    },
    #[error(
        "not a vref recording (the file starts with neither the MCAP magic nor VREFREC2 nor VREFREC1)"
    )]
    BadMagic,
    #[error("the recording is empty (0 bytes): nothing was ever written to it")]
    Empty,
    #[error("frame {frame}: length {length} exceeds the limit of {limit} bytes")]
    FrameTooLarge { frame: u64, length: u32, limit: u32 },
    #[error("frame {frame}: the file ends inside the frame")]
    Truncated { frame: u64 },
    #[error("frame {frame}: cannot decode: {message}")]
    Decode { frame: u64, message: String },
    #[error("frame {frame}: cannot encode: {message}")]
    Encode { frame: u64, message: String },
    #[error("MCAP file")]
    Mcap(#[source] mcap::McapError),
    #[error("message {message} on {topic}")]
    Wire {
        topic: &'static str,
        message: u64,
        #[source]
        source: vref_wire::bytes::BytesError,
    },
}
