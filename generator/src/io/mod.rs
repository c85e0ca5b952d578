//! Output: the sweep table (netCDF-4, `schemas/table.md`) and its reader,
//! the contact-law export (`tcgen law`: the binary law, or a `*GAP CONDUCTANCE`
//! block for CalculiX / Abaqus), surface CSV (`tcgen surface`),
//! atomic writes, hashing and provenance.

pub mod atomic;
pub mod gap_conductance;
pub mod hash;
pub mod law;
pub mod netcdf;
pub mod provenance;
pub mod surface_csv;
pub mod table;

pub use gap_conductance::{
    DeckUnits, GapConductanceOptions, GapConductanceRows, GapDeck, LawFormat, write_gap_conductance,
};
pub use law::{
    LawOptions, LawStatistic, apply_extrapolation, describe_statistic, law_from_table,
    law_from_table_with, write_law,
};
pub use netcdf::{read_table, table_to_bytes, write_table};
pub use table::{PointRecord, PointStatus, PointValues, SampleSurfaces, Table, TableInfo};
