//! The verification catalogue (spec §10), printed by `tcgen verify`.
