//! Rough surface families (spec §3).
