//! The wire types' layout as data: size, alignment, iceoryx2 type name and
//! every field's offset, size and type, read from the types themselves
//! (`size_of`, `align_of`, `offset_of!`, the `#[type_name]` attribute), so
//! that what other languages are told cannot drift from what Rust sends.
//! `vref wire-layout` prints it with the services ([`crate::ipc::catalogue`]).

// Reading a type's iceoryx2 name goes through `ZeroCopySend::type_name`,
// an `unsafe fn` only because implementing it wrongly would break the
// layout promise; calling it just returns a `&'static str`.
#![allow(unsafe_code)]

use std::mem::{align_of, offset_of, size_of};

use iceoryx2::prelude::ZeroCopySend;
use serde::Serialize;

use crate::{
    Alternative, AnswerStatus, DecisionEntry, DecisionHeader, FRAME_NAME_LEN, MAX_ALTERNATIVES,
    MAX_ANSWER_STATUSES, MAX_DECISION_PAIRS, MAX_FEATURE_DIM, MAX_REJECT_REASONS, MatcherStats,
    ObjectEntry, PointingRay, QueryKind, ReferenceAnswer, ReferenceQuery, SCHEMA_VERSION, SideCode,
    SnapshotHeader,
};

/// One field of a wire type.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Field {
    pub name: &'static str,
    /// Bytes from the start of the type.
    pub offset: usize,
    pub size: usize,
    /// `u8`, `u32`, `u64`, `f32`, another wire type's name, or an array
    /// of one of these, `[T; N]`.
    #[serde(rename = "type")]
    pub ty: String,
}

/// A `#[repr(C)]` type that crosses shared memory.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct TypeLayout {
    /// The Rust name, e.g. `SnapshotHeader`.
    pub name: &'static str,
    /// The name iceoryx2 compares when a service is opened, e.g.
    /// `vref::SnapshotHeader`: every language must declare exactly this.
    pub type_name: &'static str,
    pub size: usize,
    pub align: usize,
    /// In declaration (and offset) order.
    pub fields: Vec<Field>,
}

/// A field's type as the layout names it.
pub trait WireField {
    fn wire_type() -> String;
}

impl WireField for u8 {
    fn wire_type() -> String {
        "u8".to_owned()
    }
}

impl WireField for u32 {
    fn wire_type() -> String {
        "u32".to_owned()
    }
}

impl WireField for u64 {
    fn wire_type() -> String {
        "u64".to_owned()
    }
}

impl WireField for f32 {
    fn wire_type() -> String {
        "f32".to_owned()
    }
}

impl WireField for Alternative {
    fn wire_type() -> String {
        "Alternative".to_owned()
    }
}

impl<T: WireField, const N: usize> WireField for [T; N] {
    fn wire_type() -> String {
        format!("[{}; {N}]", T::wire_type())
    }
}

pub(crate) fn type_name_of<T: ZeroCopySend>() -> &'static str {
    // SAFETY: see the module's note; this only reads the declared name.
    unsafe { <T as ZeroCopySend>::type_name() }
}

fn field_size<S, F: WireField>(_: fn(&S) -> &F) -> usize {
    size_of::<F>()
}

fn field_type<S, F: WireField>(_: fn(&S) -> &F) -> String {
    F::wire_type()
}

/// The layout of `$ty`, whose fields must all be listed in declaration
/// order: a missing field does not compile (the destructuring below), a
/// misplaced one fails `fields_tile_every_type`.
macro_rules! layout {
    ($ty:ident { $($field:ident),* $(,)? }) => {{
        #[allow(dead_code)]
        fn every_field_is_listed(v: &$ty) {
            let $ty { $($field: _),* } = v;
        }
        TypeLayout {
            name: stringify!($ty),
            type_name: type_name_of::<$ty>(),
            size: size_of::<$ty>(),
            align: align_of::<$ty>(),
            fields: vec![$(Field {
                name: stringify!($field),
                offset: offset_of!($ty, $field),
                size: field_size(|v: &$ty| &v.$field),
                ty: field_type(|v: &$ty| &v.$field),
            }),*],
        }
    }};
}

/// Every wire type, in the order of their declaration.
pub fn wire_types() -> Vec<TypeLayout> {
    vec![
        layout!(SnapshotHeader {
            session,
            sequence,
            timestamp_ns,
            schema_version,
            side,
            object_count,
            feature_dim,
            frame_name,
            up,
            flags,
        }),
        layout!(ObjectEntry {
            track_id,
            position,
            position_sigma,
            feature,
        }),
        layout!(PointingRay {
            session,
            sequence,
            timestamp_ns,
            origin,
            direction,
            cone_half_angle,
            confidence,
            schema_version,
            reserved,
        }),
        layout!(ReferenceQuery {
            request_id,
            human_object_id,
            ray_origin,
            ray_direction,
            cone_half_angle,
            kind,
            schema_version,
            reserved,
        }),
        layout!(Alternative {
            robot_track_id,
            confidence,
            reserved,
        }),
        layout!(ReferenceAnswer {
            request_id,
            human_object_id,
            robot_track_id,
            robot_sequence,
            human_sequence,
            robot_age_us,
            human_age_us,
            solve_age_us,
            ray_age_us,
            position,
            human_frame_position,
            confidence,
            status,
            alternative_count,
            schema_version,
            alternatives,
            flags,
            refusal,
        }),
        layout!(MatcherStats {
            started_ns,
            taken_ns,
            uptime_ms,
            snapshots_received,
            snapshots_accepted,
            rejected,
            answers,
            solves,
            rss_kb,
            pid,
            schema_version,
        }),
        layout!(DecisionHeader {
            robot_session,
            robot_sequence,
            robot_timestamp_ns,
            human_session,
            human_sequence,
            human_timestamp_ns,
            solved_ns,
            solve_us,
            solve_index,
            rotation,
            translation,
            pair_count,
            flags,
            method,
            schema_version,
            residual_median,
        }),
        layout!(DecisionEntry {
            human_track_id,
            robot_track_id,
            confidence,
            status,
            flags,
            residual,
        }),
    ]
}

/// A named constant of the wire.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Constant {
    pub name: &'static str,
    pub value: u64,
}

/// The wire's sizing constants, as their Rust names.
pub fn constants() -> Vec<Constant> {
    let c = |name, value: usize| Constant {
        name,
        value: value as u64,
    };
    vec![
        Constant {
            name: "SCHEMA_VERSION",
            value: u64::from(SCHEMA_VERSION),
        },
        c("MAX_FEATURE_DIM", MAX_FEATURE_DIM),
        c("FRAME_NAME_LEN", FRAME_NAME_LEN),
        c("MAX_ALTERNATIVES", MAX_ALTERNATIVES),
        c("MAX_REJECT_REASONS", MAX_REJECT_REASONS),
        c("MAX_ANSWER_STATUSES", MAX_ANSWER_STATUSES),
        c("MAX_DECISION_PAIRS", MAX_DECISION_PAIRS),
    ]
}

/// Codes or bits of a `u32` field, by name: what a field's number means.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Codes {
    /// E.g. `AnswerStatus`, or `ReferenceAnswer.flags` for bits.
    pub name: &'static str,
    /// Where the codes are carried, e.g. `ReferenceAnswer.status`.
    pub used_in: Vec<&'static str>,
    /// `code` (a value) or `bit` (a mask to test).
    pub kind: &'static str,
    pub values: Vec<Code>,
}

/// One named code or bit.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Code {
    pub name: &'static str,
    pub value: u32,
}

fn side_name(side: SideCode) -> &'static str {
    match side {
        SideCode::Robot => "robot",
        SideCode::Human => "human",
    }
}

fn kind_name(kind: QueryKind) -> &'static str {
    match kind {
        QueryKind::HumanObject => "human_object",
        QueryKind::Ray => "ray",
        QueryKind::LatestGesture => "latest_gesture",
    }
}

/// The codes of vref-wire's enums and flag fields. (The matcher's reject
/// reasons, the index of `MatcherStats.rejected`, live with the matcher.)
pub fn codes() -> Vec<Codes> {
    let bits = |name, used_in, values: Vec<Code>| Codes {
        name,
        used_in: vec![used_in],
        kind: "bit",
        values,
    };
    vec![
        Codes {
            name: "SideCode",
            used_in: vec![
                "SnapshotHeader.side",
                "MatcherStats.snapshots_received",
                "MatcherStats.snapshots_accepted",
            ],
            kind: "code",
            values: [SideCode::Robot, SideCode::Human]
                .into_iter()
                .map(|s| Code {
                    name: side_name(s),
                    value: s as u32,
                })
                .collect(),
        },
        Codes {
            name: "QueryKind",
            used_in: vec!["ReferenceQuery.kind"],
            kind: "code",
            values: [
                QueryKind::HumanObject,
                QueryKind::Ray,
                QueryKind::LatestGesture,
            ]
            .into_iter()
            .map(|k| Code {
                name: kind_name(k),
                value: k as u32,
            })
            .collect(),
        },
        Codes {
            name: "AnswerStatus",
            used_in: vec![
                "ReferenceAnswer.status",
                "DecisionEntry.status",
                "MatcherStats.answers",
            ],
            kind: "code",
            values: AnswerStatus::ALL
                .into_iter()
                .map(|s| Code {
                    name: s.name(),
                    value: s as u32,
                })
                .collect(),
        },
        bits(
            "SnapshotHeader.flags",
            "SnapshotHeader.flags",
            vec![Code {
                name: "up",
                value: SnapshotHeader::FLAG_UP,
            }],
        ),
        bits(
            "ReferenceAnswer.flags",
            "ReferenceAnswer.flags",
            vec![
                Code {
                    name: "solved",
                    value: ReferenceAnswer::FLAG_SOLVED,
                },
                Code {
                    name: "human_position",
                    value: ReferenceAnswer::FLAG_HUMAN_POSITION,
                },
                Code {
                    name: "human_position_from_motion",
                    value: ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION,
                },
                Code {
                    name: "refusal",
                    value: ReferenceAnswer::FLAG_REFUSAL,
                },
            ],
        ),
        bits(
            "DecisionHeader.flags",
            "DecisionHeader.flags",
            vec![
                Code {
                    name: "motion",
                    value: DecisionHeader::FLAG_MOTION,
                },
                Code {
                    name: "residuals",
                    value: DecisionHeader::FLAG_RESIDUALS,
                },
            ],
        ),
        bits(
            "DecisionEntry.flags",
            "DecisionEntry.flags",
            vec![
                Code {
                    name: "partner",
                    value: DecisionEntry::FLAG_PARTNER,
                },
                Code {
                    name: "residual",
                    value: DecisionEntry::FLAG_RESIDUAL,
                },
            ],
        ),
    ]
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    /// Fields follow each other without gaps and end at the type's size:
    /// listed in declaration order, none missing, no implicit padding.
    #[test]
    fn fields_tile_every_type() {
        for t in wire_types() {
            let mut end = 0;
            for f in &t.fields {
                assert_eq!(
                    f.offset, end,
                    "{}.{} starts at {}",
                    t.name, f.name, f.offset
                );
                end += f.size;
            }
            assert_eq!(end, t.size, "{}: fields end at {end}", t.name);
            assert_eq!(t.size % t.align, 0, "{}", t.name);
        }
    }

    #[test]
    fn type_names_are_the_declared_ones() {
        for t in wire_types() {
            assert_eq!(t.type_name, format!("vref::{}", t.name));
        }
        let answer = wire_types()
            .into_iter()
            .find(|t| t.name == "ReferenceAnswer")
            .unwrap();
        let alternatives = answer
            .fields
            .iter()
            .find(|f| f.name == "alternatives")
            .unwrap();
        assert_eq!(alternatives.ty, "[Alternative; 3]");
        assert_eq!(alternatives.size, 3 * size_of::<Alternative>());
    }

    #[test]
    fn codes_are_distinct_within_each_set() {
        for set in codes() {
            let mut values: Vec<u32> = set.values.iter().map(|c| c.value).collect();
            values.sort_unstable();
            values.dedup();
            assert_eq!(values.len(), set.values.len(), "{}", set.name);
        }
    }
}
