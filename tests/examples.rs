//! The README's Rust examples (examples/), run as tests: each one's `main` must succeed on
//! the shipped robots and paths, so that a change of a default (a new feasibility margin, a
//! renamed option) cannot leave an example that stops with an error.

#[path = "../examples/energy_at_placement.rs"]
mod energy_at_placement;

#[path = "../examples/sweep.rs"]
mod sweep;

#[path = "../examples/compare_log.rs"]
mod compare_log;

#[test]
fn the_energy_at_placement_example_runs() {
    energy_at_placement::main().expect("examples/energy_at_placement.rs failed");
}

#[test]
fn the_sweep_example_finds_a_feasible_placement_under_the_default_checks() {
    sweep::main().expect("examples/sweep.rs failed");
}

#[test]
fn the_compare_log_example_runs() {
    compare_log::main().expect("examples/compare_log.rs failed");
}
