//! cargo fuzz target: the measurement-log reader. Any panic is a bug; errors are fine (tests/fuzz_mutation.rs checks
//! that they are located).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = printwatt::error::decode_text(data, "fuzz.csv") else {
        return;
    };
    let _ = printwatt::identify::log::parse_log(&text, "fuzz.csv", 6, None);
});
