//! cargo fuzz target: the joint-trajectory CSV reader. Any panic is a bug; errors are fine (tests/fuzz_mutation.rs checks
//! that they are located).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = printwatt::error::decode_text(data, "fuzz.csv") else {
        return;
    };
    if let Ok(t) =
        printwatt::table::Table::parse(&text, "fuzz.csv", &printwatt::trajectory::trajectory_dim)
    {
        let _ = printwatt::trajectory::from_table(&t, 6);
    }
});
