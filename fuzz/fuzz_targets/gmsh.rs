#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use tessera_data::tet::gmsh;

fuzz_target!(|data: &[u8]| {
    let file = "input.msh";
    common::names_file(&gmsh::parse_bytes(data, common::path(file)), file);
});
