//! Whatever bytes a dataset file holds, the reader yields scene pairs or
//! errors and ends; it never panics.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vref_scene::{DatasetReader, Limits};

fuzz_target!(|data: &[u8]| {
    for item in DatasetReader::new(data, Limits::default()) {
        let _ = item;
    }
});
