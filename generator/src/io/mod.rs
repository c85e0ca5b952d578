//! Output: the sweep table (netCDF-4, `schemas/table.md`) and its reader,
//! the contact-law export (`tcgen law`), surface CSV (`tcgen surface`),
//! atomic writes, hashing and provenance.

pub mod atomic;
pub mod hash;
pub mod law;
pub mod netcdf;
pub mod provenance;
pub mod surface_csv;
pub mod table;

pub use law::{
    LawOptions, LawStatistic, apply_extrapolation, law_from_table, law_from_table_with, write_law,
};
pub use netcdf::{read_table, table_to_bytes, write_table};
pub use table::{PointRecord, PointStatus, PointValues, SampleSurfaces, Table, TableInfo};
