#![no_main]

use libfuzzer_sys::fuzz_target;
use tessera_data::sniff::sniff_bytes;

fuzz_target!(|data: &[u8]| {
    // The file sniffer looks at the first 4096 bytes.
    if let Some(found) = sniff_bytes(&data[..data.len().min(4096)]) {
        let _ = (found.is_mesh(), found.describe());
    }
});
