//! cargo fuzz target: the URDF reader. Any panic is a bug; errors are fine (tests/fuzz_mutation.rs checks
//! that they are located).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = printwatt::error::decode_text(data, "fuzz.urdf") else {
        return;
    };
    let _ = printwatt::robot::urdf::check_xml_depth(&text, "fuzz.urdf", 64)
        .and_then(|_| printwatt::robot::urdf::parse_urdf(&text, "fuzz.urdf", None));
});
