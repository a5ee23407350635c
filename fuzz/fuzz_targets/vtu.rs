#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use tessera_data::tet::vtu;

fuzz_target!(|data: &[u8]| {
    let file = "input.vtu";
    common::names_file(&vtu::parse_bytes(data, common::path(file)), file);
});
