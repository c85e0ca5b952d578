//! Homogenization procedures (paper Sects. 2–3, spec §8): the accompanying
//! bar problem, the original heterogeneous problem with the θ̄c-projection
//! (2.12), and the identifications of the macroscopic jump: coupled (2.14),
//! linearized (3.4), two-phase (Sect. 3.1) and two-phase self-consistent
//! (Sect. 3.3).

pub mod abp;
pub mod adapt;
pub mod hbp;
pub mod path;
pub mod recovery;

pub use abp::{AbpProperties, AbpTemperatures, accompanying_bar};
pub use path::{LevelObserver, LevelReport, PointResult, Status, solve_case, solve_case_observed};
