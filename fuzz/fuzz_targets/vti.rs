#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use tessera_data::{vti, NanPolicy};

fuzz_target!(|data: &[u8]| {
    let file = "input.vti";
    common::names_file(
        &vti::parse_bytes(data, common::path(file), NanPolicy::Reject),
        file,
    );
});
