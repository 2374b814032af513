//! cargo fuzz target: the ABB RAPID reader. Any panic is a bug; errors are fine (tests/fuzz_mutation.rs checks
//! that they are located).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = printwatt::error::decode_text(data, "fuzz.mod") else {
        return;
    };
    if let Ok(tp) = printwatt::toolpath::parse_rapid(&text, "fuzz.mod", &Default::default()) {
        let _ = printwatt::toolpath::check_extent(&tp, "fuzz.mod");
    }
});
