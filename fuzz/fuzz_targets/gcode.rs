//! cargo fuzz target: the G-code reader. Any panic is a bug; errors are fine (tests/fuzz_mutation.rs checks
//! that they are located).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = printwatt::error::decode_text(data, "fuzz.gcode") else {
        return;
    };
    if let Ok(tp) = printwatt::toolpath::parse_gcode(&text, "fuzz.gcode", &Default::default()) {
        let _ = printwatt::toolpath::check_extent(&tp, "fuzz.gcode");
    }
});
