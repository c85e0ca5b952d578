//! Performance figures printed by `tcgen bench`.
