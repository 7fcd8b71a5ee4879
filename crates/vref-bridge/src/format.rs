//! The two encodings every bridged message travels in, as declared in
//! Zenoh's encoding field: JSON (`application/json`) and the wire's own
//! binary layout (`application/octet-stream;vref::<Message>@<schema>`).
//! Binary payloads name their message and schema version, so a payload of
//! another type or version is refused by its label before any byte of it
//! is read.

use vref_config::StateEncoding;
use vref_wire::SCHEMA_VERSION;

use crate::CodecError;

/// `application/json`, no schema.
pub const JSON: &str = "application/json";
/// The MIME type of binary payloads; the schema says which message.
pub const OCTET_STREAM: &str = "application/octet-stream";

/// How a payload is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Json,
    Binary,
}

impl Format {
    pub fn name(self) -> &'static str {
        match self {
            Format::Json => "json",
            Format::Binary => "binary",
        }
    }
}

/// The encoding `[bridge] state_encoding` names.
impl From<StateEncoding> for Format {
    fn from(encoding: StateEncoding) -> Self {
        match encoding {
            StateEncoding::Json => Format::Json,
            StateEncoding::Binary => Format::Binary,
        }
    }
}

impl std::str::FromStr for Format {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "json" => Ok(Format::Json),
            "binary" => Ok(Format::Binary),
            other => Err(format!("`{other}` is not an encoding (json or binary)")),
        }
    }
}

/// Which message a payload carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Message {
    /// A snapshot header and its objects.
    Snapshot,
    Ray,
    Query,
    Answer,
    Stats,
    /// A decision header and its pairs.
    Decision,
}

impl Message {
    fn type_name(self) -> &'static str {
        match self {
            Message::Snapshot => "Snapshot",
            Message::Ray => "PointingRay",
            Message::Query => "ReferenceQuery",
            Message::Answer => "ReferenceAnswer",
            Message::Stats => "MatcherStats",
            Message::Decision => "Decision",
        }
    }

    /// The schema of the binary encoding, e.g. `vref::PointingRay@2`.
    pub fn schema(self) -> String {
        format!("vref::{}@{SCHEMA_VERSION}", self.type_name())
    }

    /// The full encoding string of this message in `format`.
    pub fn encoding(self, format: Format) -> String {
        match format {
            Format::Json => JSON.to_owned(),
            Format::Binary => format!("{OCTET_STREAM};{}", self.schema()),
        }
    }

    /// The format a payload labelled `encoding` is in, if it is one of
    /// this message's two.
    pub fn format_of(self, encoding: &str) -> Result<Format, CodecError> {
        if encoding == JSON {
            return Ok(Format::Json);
        }
        let binary = self.encoding(Format::Binary);
        if encoding == binary {
            return Ok(Format::Binary);
        }
        Err(CodecError::Encoding {
            found: encoding.to_owned(),
            json: JSON,
            binary,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_state_encoding_setting_names_its_format() {
        assert_eq!(Format::from(StateEncoding::Json), Format::Json);
        assert_eq!(Format::from(StateEncoding::Binary), Format::Binary);
    }

    #[test]
    fn only_the_two_declared_encodings_of_the_message_are_accepted() {
        let m = Message::Snapshot;
        assert_eq!(m.format_of("application/json"), Ok(Format::Json));
        let binary = format!("application/octet-stream;vref::Snapshot@{SCHEMA_VERSION}");
        assert_eq!(m.encoding(Format::Binary), binary);
        assert_eq!(m.format_of(&binary), Ok(Format::Binary));
        for bad in [
            "application/octet-stream",
            "zenoh/bytes",
            "text/plain",
            "application/json;x",
            "application/octet-stream;vref::PointingRay@2",
            &format!(
                "application/octet-stream;vref::Snapshot@{}",
                SCHEMA_VERSION + 1
            ),
        ] {
            assert!(m.format_of(bad).is_err(), "{bad}");
        }
    }
}
