#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use tessera_data::{nrrd, NanPolicy};

fuzz_target!(|data: &[u8]| {
    let file = "input.nrrd";
    common::names_file(
        &nrrd::parse_bytes(data, common::path(file), NanPolicy::Reject),
        file,
    );
    let _ = nrrd::parse_bytes(data, common::path(file), NanPolicy::Replace(0.0));
});
