//! Parameter sweeps over pressure, flux, contact temperature and surface samples.
