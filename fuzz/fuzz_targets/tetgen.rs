#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use tessera_data::tet::tetgen;

// The input is the .node file, a NUL byte, then the .ele file (no NUL: an empty .ele).
fuzz_target!(|data: &[u8]| {
    let split = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    let (node, ele) = (&data[..split], data.get(split + 1..).unwrap_or(&[]));
    let result = tetgen::parse_bytes(
        node,
        common::path("input.node"),
        ele,
        common::path("input.ele"),
    );
    if let Err(e) = &result {
        let text = e.to_string();
        assert!(text.contains("input."), "error names neither file: {text}");
    }
});
