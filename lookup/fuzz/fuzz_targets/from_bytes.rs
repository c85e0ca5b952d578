//! Arbitrary bytes: `Law::from_bytes` returns an error or a valid law, never panics.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use lookup::Law;

fuzz_target!(|data: &[u8]| {
    if let Ok(law) = Law::from_bytes(data) {
        common::exercise(&law);
    }
});
