#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use tessera_data::tet::vtk_legacy;

fuzz_target!(|data: &[u8]| {
    let file = "input.vtk";
    common::names_file(&vtk_legacy::parse_bytes(data, common::path(file)), file);
});
