//! cargo fuzz target: the drive TOML reader, through `robot::load` (the drive file is read
//! with a shipped URDF beside it, as users load robots). Any panic is a bug.
#![no_main]
use libfuzzer_sys::fuzz_target;

const URDF: &str = include_str!("../../robots/abb_irb4600_40_255/robot.urdf");

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("printwatt-fuzz-drive-{}", std::process::id()));
    if std::fs::create_dir_all(&dir).is_err() {
        return;
    }
    if std::fs::write(dir.join("robot.urdf"), URDF).is_err()
        || std::fs::write(dir.join("drive.toml"), data).is_err()
    {
        return;
    }
    let _ = printwatt::robot::load(&dir);
});
