//! Campaigns of many runs: design studies (robots × cells × paths, each case optimised) and
//! the shards a sweep, an uncertainty study or a study is split into and merged from.

pub mod shard;
pub mod study;
