//! Whatever a publisher writes into a snapshot's shared memory, validation
//! returns a snapshot or a typed error; it never panics.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vref_scene::Limits;
use vref_wire::fuzz_input::snapshot_from_bytes;
use vref_wire::validate_snapshot;

fuzz_target!(|data: &[u8]| {
    let s = snapshot_from_bytes(data);
    let _ = validate_snapshot(&s.header, &s.entries, s.expected, &Limits::default());
});
