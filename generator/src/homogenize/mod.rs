//! Homogenization procedures (paper Sects. 2–3, spec §8).
