//! Arbitrary bytes with a correct CRC-32 written over their last 4 bytes, so
//! that the fuzzer reaches the size, metadata and value checks behind the checksum.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use lookup::{Law, crc32};

fuzz_target!(|data: &[u8]| {
    if data.len() < 4 {
        let _ = Law::from_bytes(data);
        return;
    }
    let mut bytes = data.to_vec();
    let body = bytes.len() - 4;
    let crc = crc32(&bytes[..body]);
    bytes[body..].copy_from_slice(&crc.to_le_bytes());
    if let Ok(law) = Law::from_bytes(&bytes) {
        common::exercise(&law);
    }
});
