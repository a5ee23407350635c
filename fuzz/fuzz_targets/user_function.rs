#![no_main]

use libfuzzer_sys::fuzz_target;
use tessera_data::param::user::UserFunction;

// Either with the ranges from the file or given on the command line.
fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let name = "input.glsl";
    for (u, v) in [(None, None), (Some([0.0, 1.0]), Some([-1.0, 1.0]))] {
        if let Err(e) = UserFunction::from_text(name, text, u, v) {
            let text = e.to_string();
            assert!(text.contains(name), "error does not name {name}: {text}");
        }
    }
});
