#![no_main]

use libfuzzer_sys::fuzz_target;
use tessera_data::transfer::TransferFunction;

fuzz_target!(|data: &[u8]| {
    // The file loader refuses what is not UTF-8 before parsing.
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(tf) = TransferFunction::parse(text) {
        for x in [-1.0, 0.0, 0.25, 0.5, 1.0, 2.0, f64::NAN] {
            let _ = tf.sample(x);
        }
    }
});
