//! Mortar-based frictionless mechanical and thermal contact (paper Sect. 4, spec §6).
