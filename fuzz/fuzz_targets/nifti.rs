#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use tessera_data::{nifti, NanPolicy};

fuzz_target!(|data: &[u8]| {
    let file = "input.nii";
    common::names_file(
        &nifti::parse_bytes(data, common::path(file), NanPolicy::Reject),
        file,
    );
    let _ = nifti::parse_bytes(data, common::path(file), NanPolicy::Replace(0.0));
});
