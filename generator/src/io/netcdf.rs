//! The table file: netCDF-4 (HDF5) written by the pure-Rust `netcdf-writer`
//! and read back by `netcdf-reader`. Layout and attributes: `schemas/table.md`.
//!
//! Dimensions `pressure`, `flux`, `contact_temperature`, `sample`, `quantile`,
//! each with its coordinate variable. Masked values (failed or not computed
//! points, empty ensembles) hold `_FillValue` (NC_FILL_DOUBLE, NC_FILL_INT),
//! never NaN; `status` says why.

use std::path::Path;

use netcdf_writer::{
    DimensionId, NC_FILL_DOUBLE, NC_FILL_INT, NcAttrValue, NcFileBuilder, NcWriteFormat,
    NcWriteOptions, VariableId,
};

use crate::io::table::{
    PointRecord, PointStatus, PointValues, SCHEMA_NAME, SCHEMA_VERSION, SampleSurfaces, Table,
    TableInfo,
};
use crate::surface::random::RANDOM_SURFACE_VERSION;
use crate::sweep::Shard;
use crate::sweep::ensemble::{QUANTILES, Summary};
use crate::{Error, Result};

/// Fill value of masked floating-point values (netCDF's default for doubles).
pub const FILL_DOUBLE: f64 = NC_FILL_DOUBLE;
/// Fill value of masked integer values.
pub const FILL_INT: i32 = NC_FILL_INT;

/// The sign conventions, stored as the global attribute `sign_convention`.
pub const SIGN_CONVENTION: &str = "pressure > 0 in compression; flux is the magnitude |h| of the \
heat flowing from body 1 (upper, slave) to body 2 (lower, master), so h < 0 in the paper's \
convention (Temizer 2014, Sect. 2); jump = theta - theta_c > 0 is the macroscopic temperature \
jump of Eq. (2.6); conductance = |h| / jump > 0 (Eq. (2.7)); contact_temperature theta_c is the \
temperature on the master (body 2) side";

fn nc_err(what: &str) -> impl Fn(netcdf_writer::Error) -> Error + '_ {
    move |e| Error::Io {
        path: what.to_string(),
        source: std::io::Error::other(e.to_string()),
    }
}

struct Writer {
    b: NcFileBuilder,
}

impl Writer {
    fn attr(&mut self, v: VariableId, name: &str, value: NcAttrValue) -> Result<()> {
        self.b
            .add_variable_attribute(v, name, value)
            .map_err(nc_err("table"))
    }

    fn text(&mut self, v: VariableId, name: &str, value: &str) -> Result<()> {
        self.attr(v, name, NcAttrValue::Chars(value.into()))
    }

    /// `long_name` (a short label, for plot axes) and, after ` | `, the
    /// `comment` (the definition, equation numbers).
    fn labels(&mut self, v: VariableId, text: &str) -> Result<()> {
        match text.split_once(" | ") {
            Some((label, comment)) => {
                self.text(v, "long_name", label)?;
                self.text(v, "comment", comment)
            }
            None => self.text(v, "long_name", text),
        }
    }

    fn doubles(
        &mut self,
        name: &str,
        dims: &[DimensionId],
        units: &str,
        long_name: &str,
        data: &[f64],
        masked: bool,
    ) -> Result<VariableId> {
        let v = self
            .b
            .add_variable::<f64>(name, dims)
            .map_err(nc_err(name))?;
        if masked {
            self.b
                .set_variable_fill_value(v, FILL_DOUBLE)
                .map_err(nc_err(name))?;
        }
        self.text(v, "units", units)?;
        self.labels(v, long_name)?;
        self.b.write_variable(v, data).map_err(nc_err(name))?;
        Ok(v)
    }

    fn ints(
        &mut self,
        name: &str,
        dims: &[DimensionId],
        units: &str,
        long_name: &str,
        data: &[i32],
        masked: bool,
    ) -> Result<VariableId> {
        let v = self
            .b
            .add_variable::<i32>(name, dims)
            .map_err(nc_err(name))?;
        if masked {
            self.b
                .set_variable_fill_value(v, FILL_INT)
                .map_err(nc_err(name))?;
        }
        self.text(v, "units", units)?;
        self.labels(v, long_name)?;
        self.b.write_variable(v, data).map_err(nc_err(name))?;
        Ok(v)
    }

    fn global(&mut self, name: &str, value: NcAttrValue) -> Result<()> {
        self.b.add_attribute(name, value).map_err(nc_err(name))
    }
}

fn masked<T: Copy>(values: &[Option<T>], f: impl Fn(T) -> f64) -> Vec<f64> {
    values.iter().map(|v| v.map_or(FILL_DOUBLE, &f)).collect()
}

/// The netCDF-4 bytes of a table (deterministic: the same table gives the same bytes).
pub fn table_to_bytes(t: &Table) -> Result<Vec<u8>> {
    t.check()?;
    let mut w = Writer {
        b: NcFileBuilder::new(),
    };
    let [np, nh, nt, ns] = t.shape();
    let dim = |w: &mut Writer, name: &str, n: usize| {
        w.b.add_dimension(name, n as u64).map_err(nc_err(name))
    };
    let dp = dim(&mut w, "pressure", np)?;
    let dh = dim(&mut w, "flux", nh)?;
    let dt = dim(&mut w, "contact_temperature", nt)?;
    let ds = dim(&mut w, "sample", ns)?;
    let dq = dim(&mut w, "quantile", QUANTILES.len())?;

    // Coordinates.
    w.doubles(
        "pressure",
        &[dp],
        "Pa",
        "contact pressure | macroscopic contact pressure p_N (positive in compression)",
        &t.pressure,
        false,
    )?;
    w.doubles(
        "flux",
        &[dh],
        "W m-2",
        "heat flux | magnitude |h| of the macroscopic heat flux, from body 1 (upper) to body 2 (lower)",
        &t.flux,
        false,
    )?;
    w.doubles(
        "contact_temperature",
        &[dt],
        "K",
        "macroscopic contact temperature theta_c (master side)",
        &t.contact_temperature,
        false,
    )?;
    let samples: Vec<i32> = (0..ns as i32).collect();
    w.ints(
        "sample",
        &[ds],
        "1",
        "sample | surface sample index s of the ensemble (random stream of schemas/table.md)",
        &samples,
        false,
    )?;
    w.doubles(
        "quantile",
        &[dq],
        "1",
        "quantile level over the samples",
        &QUANTILES,
        false,
    )?;

    // Per point and sample.
    let d4 = [dp, dh, dt, ds];
    let status: Vec<i8> = t.points.iter().map(|p| p.status as i8).collect();
    let v =
        w.b.add_variable::<i8>("status", &d4)
            .map_err(nc_err("status"))?;
    w.text(v, "units", "1")?;
    w.text(v, "long_name", "status of the micro-solve of the point")?;
    w.attr(v, "flag_values", NcAttrValue::Bytes(vec![0, 1, 2]))?;
    let meanings = [
        PointStatus::Converged,
        PointStatus::Failed,
        PointStatus::NotComputed,
    ]
    .map(PointStatus::meaning)
    .join(" ");
    w.text(v, "flag_meanings", &meanings)?;
    w.b.write_variable(v, &status).map_err(nc_err("status"))?;
    let v =
        w.b.add_string_variable("failure_reason", &d4)
            .map_err(nc_err("failure_reason"))?;
    w.text(
        v,
        "long_name",
        "why the point failed (empty when converged)",
    )?;
    let reasons: Vec<&str> = t.points.iter().map(|p| p.reason.as_str()).collect();
    w.b.write_string_variable(v, &reasons)
        .map_err(nc_err("failure_reason"))?;
    let values: Vec<Option<PointValues>> = t.points.iter().map(|p| p.values).collect();
    w.doubles(
        "jump",
        &d4,
        "K",
        "temperature jump | macroscopic temperature jump theta - theta_c across the interface, Eq. (2.6)",
        &masked(&values, |v| v.jump),
        true,
    )?;
    w.doubles(
        "conductance",
        &d4,
        "W m-2 K-1",
        "contact conductance | macroscopic contact conductance |h| / jump, Eq. (2.7)",
        &masked(&values, |v| v.conductance),
        true,
    )?;
    w.doubles(
        "contact_fraction",
        &d4,
        "1",
        "contact fraction | real contact area fraction (projected on the mean plane)",
        &masked(&values, |v| v.contact_fraction),
        true,
    )?;
    w.doubles(
        "mean_gap",
        &d4,
        "m",
        "mean gap over the slave surface",
        &masked(&values, |v| v.mean_gap),
        true,
    )?;
    let iters = |f: fn(&PointValues) -> u32| -> Vec<i32> {
        values
            .iter()
            .map(|v| {
                v.as_ref()
                    .map_or(FILL_INT, |v| f(v).min(i32::MAX as u32) as i32)
            })
            .collect()
    };
    w.ints(
        "self_consistency_iterations",
        &d4,
        "1",
        "self-consistency iterations | of the two-phase identification (Sect. 3.3)",
        &iters(|v| v.self_consistency_iterations),
        true,
    )?;
    w.ints(
        "newton_iterations",
        &d4,
        "1",
        "Newton iterations of the point, all phases",
        &iters(|v| v.newton_iterations),
        true,
    )?;
    w.doubles(
        "jump_error",
        &d4,
        "K",
        "jump discretization error | estimated discretization error of the jump (two-level estimate of the adaptive refinement; missing on a fixed mesh)",
        &values
            .iter()
            .map(|v| v.and_then(|v| v.jump_error).unwrap_or(FILL_DOUBLE))
            .collect::<Vec<_>>(),
        true,
    )?;
    w.ints(
        "error_target_met",
        &d4,
        "1",
        "error target met | 1 where the error estimate met discretization.target_error, 0 where not (missing on a fixed mesh)",
        &values
            .iter()
            .map(|v| {
                v.and_then(|v| v.error_target_met)
                    .map_or(FILL_INT, i32::from)
            })
            .collect::<Vec<_>>(),
        true,
    )?;
    w.ints(
        "dofs",
        &d4,
        "1",
        "unknowns of the mesh of the jump",
        &iters(|v| v.dofs),
        true,
    )?;

    // Per sample.
    let s = &t.surfaces;
    w.doubles(
        "upper_surface_rms",
        &[ds],
        "m",
        "RMS roughness of the upper surface (body 1) of the sample",
        &masked(s, |v: SampleSurfaces| v.upper_rms),
        true,
    )?;
    w.doubles(
        "lower_surface_rms",
        &[ds],
        "m",
        "RMS roughness of the lower surface (body 2) of the sample",
        &masked(s, |v: SampleSurfaces| v.lower_rms),
        true,
    )?;
    w.doubles(
        "upper_fit_error",
        &[ds],
        "m",
        "upper fit error | largest height error of the NURBS fit of the upper surface",
        &masked(s, |v: SampleSurfaces| v.upper_fit_error),
        true,
    )?;
    w.doubles(
        "lower_fit_error",
        &[ds],
        "m",
        "lower fit error | largest height error of the NURBS fit of the lower surface",
        &masked(s, |v: SampleSurfaces| v.lower_fit_error),
        true,
    )?;

    // Ensemble statistics.
    let st = t.statistics();
    let d3 = [dp, dh, dt];
    let conv: Vec<i32> = st.converged.iter().map(|&n| n as i32).collect();
    w.ints(
        "converged_samples",
        &d3,
        "1",
        "converged samples | number of converged samples behind the ensemble statistics",
        &conv,
        false,
    )?;
    for (name, units, stats) in [
        ("jump", "K", &st.jump),
        ("conductance", "W m-2 K-1", &st.conductance),
    ] {
        // Missing (never NaN) where there is no value: no converged sample,
        // or a spread from a single one.
        let field = |f: fn(&Summary) -> f64| -> Vec<f64> {
            stats
                .iter()
                .map(|s| {
                    s.as_ref()
                        .map(f)
                        .filter(|v| !v.is_nan())
                        .unwrap_or(FILL_DOUBLE)
                })
                .collect()
        };
        w.doubles(
            &format!("{name}_mean"),
            &d3,
            units,
            &format!("mean {name} | ensemble mean of the {name} over the converged samples"),
            &field(|s| s.mean),
            true,
        )?;
        w.doubles(
            &format!("{name}_std"),
            &d3,
            units,
            &format!("{name} std | ensemble standard deviation (n - 1) of the {name}"),
            &field(|s| s.std),
            true,
        )?;
        w.doubles(
            &format!("{name}_sem"),
            &d3,
            units,
            &format!("{name} sem | standard error of the ensemble mean of the {name}"),
            &field(|s| s.sem),
            true,
        )?;
        let q: Vec<f64> = stats
            .iter()
            .flat_map(|s| match s {
                Some(s) => s.quantiles,
                None => [FILL_DOUBLE; QUANTILES.len()],
            })
            .collect();
        w.doubles(
            &format!("{name}_quantile"),
            &[dp, dh, dt, dq],
            units,
            &format!("{name} quantiles | ensemble quantiles of the {name} (linear interpolation, numpy's default)"),
            &q,
            true,
        )?;
    }
    w.doubles(
        "jump_discretization_error",
        &d3,
        "K",
        "discretization error of jump_mean | the mean of the samples' jump_error (missing on fixed meshes)",
        &st.jump_discretization_error
            .iter()
            .map(|e| e.unwrap_or(FILL_DOUBLE))
            .collect::<Vec<_>>(),
        true,
    )?;

    // The configuration, as a scalar string variable (attributes over ~64 KB fail).
    let v =
        w.b.add_string_variable("config", &[])
            .map_err(nc_err("config"))?;
    w.text(v, "long_name", "the resolved sweep configuration (TOML)")?;
    w.b.write_string_variable(v, &[t.info.config.as_str()])
        .map_err(nc_err("config"))?;

    // Global attributes.
    let i = &t.info;
    w.global("Conventions", NcAttrValue::Chars("CF-1.8".into()))?;
    w.global("title", NcAttrValue::Chars("tcgen thermal contact table: macroscopic temperature jump over pressure x flux x contact temperature x surface samples".into()))?;
    w.global("schema", NcAttrValue::Chars(SCHEMA_NAME.into()))?;
    w.global("schema_version", NcAttrValue::Ints(vec![SCHEMA_VERSION]))?;
    w.global(
        "random_surface_version",
        NcAttrValue::Ints(vec![RANDOM_SURFACE_VERSION as i32]),
    )?;
    w.global("generator", NcAttrValue::Chars(i.generator.clone()))?;
    w.global("git_revision", NcAttrValue::Chars(i.git_revision.clone()))?;
    w.global("source", NcAttrValue::Chars(i.source.clone()))?;
    w.global("config_sha256", NcAttrValue::Chars(i.config_sha256.clone()))?;
    w.global("seed", NcAttrValue::Int64s(vec![i.seed as i64]))?;
    if let Some((dimension, cell)) = crate::io::table::sample_cell(&i.config) {
        w.global("dimension", NcAttrValue::Ints(vec![dimension as i32]))?;
        w.global("cell_size", NcAttrValue::Doubles(cell))?;
    }
    w.global("samples", NcAttrValue::Ints(vec![ns as i32]))?;
    w.global(
        "identification",
        NcAttrValue::Chars(i.identification.clone()),
    )?;
    w.global(
        "sign_convention",
        NcAttrValue::Chars(SIGN_CONVENTION.into()),
    )?;
    w.global("created", NcAttrValue::Chars(i.created.clone()))?;
    // The attributes NCO and CF tools expect.
    w.global(
        "history",
        NcAttrValue::Chars(format!("{}: {} sweep {}", i.created, i.generator, i.source)),
    )?;
    w.global(
        "references",
        NcAttrValue::Chars(
            "I. Temizer, Multiscale thermomechanical contact: computational homogenization with \
             isogeometric analysis, Int. J. Numer. Meth. Engng (2014); schemas/table.md"
                .into(),
        ),
    )?;
    w.global("wall_time", NcAttrValue::Doubles(vec![i.wall_time]))?;
    w.global("threads", NcAttrValue::Ints(i.threads.clone()))?;
    w.global(
        "converged_points",
        NcAttrValue::Ints(vec![t.count(PointStatus::Converged) as i32]),
    )?;
    w.global(
        "failed_points",
        NcAttrValue::Ints(vec![t.count(PointStatus::Failed) as i32]),
    )?;
    if !i.cautions.is_empty() {
        w.global("cautions", NcAttrValue::Chars(i.cautions.join("\n")))?;
    }
    if let Some(sh) = i.shard {
        w.global("shard_index", NcAttrValue::Ints(vec![sh.index as i32]))?;
        w.global("shard_count", NcAttrValue::Ints(vec![sh.count as i32]))?;
    }
    let (_, bytes) =
        w.b.to_vec(NcWriteOptions {
            format: NcWriteFormat::Nc4,
        })
        .map_err(nc_err("table"))?;
    Ok(bytes)
}

/// Writes a table atomically (a killed writer leaves no partial file at `path`).
pub fn write_table(t: &Table, path: &Path) -> Result<()> {
    let bytes = table_to_bytes(t)?;
    crate::io::atomic::write_atomic(path, &bytes)
}

fn rd_err(path: &Path) -> impl Fn(netcdf_reader::Error) -> Error + '_ {
    move |e| Error::Io {
        path: path.display().to_string(),
        source: std::io::Error::other(e.to_string()),
    }
}

/// Reads a table written by [`write_table`] (any shard or a merged table).
pub fn read_table(path: &Path) -> Result<Table> {
    let f = netcdf_reader::NcFile::open(path).map_err(rd_err(path))?;
    let text = |name: &str| -> Result<String> {
        f.global_attribute(name)
            .map_err(rd_err(path))?
            .value
            .as_string()
            .ok_or_else(|| {
                Error::Config(format!("{}: attribute {name} is not text", path.display()))
            })
    };
    let ints = |name: &str| -> Result<Vec<i64>> {
        let a = &f.global_attribute(name).map_err(rd_err(path))?.value;
        Ok(match a {
            NcAttrValue::Ints(v) => v.iter().map(|&x| x as i64).collect(),
            NcAttrValue::Int64s(v) => v.clone(),
            other => {
                return Err(Error::Config(format!(
                    "{}: attribute {name} is {other:?}, expected integers",
                    path.display()
                )));
            }
        })
    };
    let schema = text("schema")?;
    let version = ints("schema_version")?;
    if schema != SCHEMA_NAME || version != [i64::from(SCHEMA_VERSION)] {
        return Err(Error::Config(format!(
            "{}: schema {schema} version {version:?}; this tcgen reads {SCHEMA_NAME} version {SCHEMA_VERSION}",
            path.display()
        )));
    }
    let f64s = |name: &str| -> Result<Vec<f64>> {
        Ok(f.read_variable::<f64>(name)
            .map_err(rd_err(path))?
            .into_iter()
            .collect())
    };
    let i32s = |name: &str| -> Result<Vec<i32>> {
        Ok(f.read_variable::<i32>(name)
            .map_err(rd_err(path))?
            .into_iter()
            .collect())
    };
    let pressure = f64s("pressure")?;
    let flux = f64s("flux")?;
    let contact_temperature = f64s("contact_temperature")?;
    let samples = i32s("sample")?.len();
    let status: Vec<i8> = f
        .read_variable::<i8>("status")
        .map_err(rd_err(path))?
        .into_iter()
        .collect();
    let reasons = f
        .read_variable_as_strings("failure_reason")
        .map_err(rd_err(path))?;
    let (jump, conductance) = (f64s("jump")?, f64s("conductance")?);
    let (fraction, gap) = (f64s("contact_fraction")?, f64s("mean_gap")?);
    let (sc, nw) = (
        i32s("self_consistency_iterations")?,
        i32s("newton_iterations")?,
    );
    let (jerr, met, dofs) = (
        f64s("jump_error")?,
        i32s("error_target_met")?,
        i32s("dofs")?,
    );
    let n = pressure.len() * flux.len() * contact_temperature.len() * samples;
    for (name, len) in [
        ("status", status.len()),
        ("failure_reason", reasons.len()),
        ("jump", jump.len()),
        ("newton_iterations", nw.len()),
        ("jump_error", jerr.len()),
        ("error_target_met", met.len()),
        ("dofs", dofs.len()),
    ] {
        if len != n {
            return Err(Error::Config(format!(
                "{}: {name} has {len} values for a grid of {n}",
                path.display()
            )));
        }
    }
    let mut points = Vec::with_capacity(n);
    for i in 0..n {
        let st = PointStatus::from_code(status[i]).ok_or_else(|| {
            Error::Config(format!(
                "{}: status code {} at point {i}",
                path.display(),
                status[i]
            ))
        })?;
        points.push(PointRecord {
            status: st,
            reason: reasons[i].clone(),
            values: (st == PointStatus::Converged).then(|| PointValues {
                jump: jump[i],
                conductance: conductance[i],
                contact_fraction: fraction[i],
                mean_gap: gap[i],
                self_consistency_iterations: sc[i].max(0) as u32,
                newton_iterations: nw[i].max(0) as u32,
                jump_error: (jerr[i] != FILL_DOUBLE && jerr[i].is_finite()).then_some(jerr[i]),
                error_target_met: (met[i] != FILL_INT).then_some(met[i] != 0),
                dofs: dofs[i].max(0) as u32,
            }),
        });
    }
    let su = [
        f64s("upper_surface_rms")?,
        f64s("lower_surface_rms")?,
        f64s("upper_fit_error")?,
        f64s("lower_fit_error")?,
    ];
    let surfaces = (0..samples)
        .map(|s| {
            (su[0][s] != FILL_DOUBLE).then(|| SampleSurfaces {
                upper_rms: su[0][s],
                lower_rms: su[1][s],
                upper_fit_error: su[2][s],
                lower_fit_error: su[3][s],
            })
        })
        .collect();
    let shard = match (ints("shard_index"), ints("shard_count")) {
        (Ok(i), Ok(c)) if i.len() == 1 && c.len() == 1 => {
            Some(Shard::new(i[0] as usize, c[0] as usize)?)
        }
        _ => None,
    };
    let wall = match &f.global_attribute("wall_time").map_err(rd_err(path))?.value {
        NcAttrValue::Doubles(v) if v.len() == 1 => v[0],
        other => {
            return Err(Error::Config(format!(
                "{}: wall_time is {other:?}",
                path.display()
            )));
        }
    };
    let info = TableInfo {
        config: f.read_variable_as_string("config").map_err(rd_err(path))?,
        config_sha256: text("config_sha256")?,
        source: text("source")?,
        seed: ints("seed")?.first().copied().unwrap_or(0) as u64,
        identification: text("identification")?,
        generator: text("generator")?,
        git_revision: text("git_revision")?,
        created: text("created")?,
        wall_time: wall,
        threads: ints("threads")?.iter().map(|&x| x as i32).collect(),
        shard,
        // One caution per line; the attribute is absent where there are none
        // (a file that cannot list its attributes, or whose `cautions` cannot
        // be read, is an error, not a table without cautions).
        cautions: if f
            .global_attributes()
            .map_err(rd_err(path))?
            .iter()
            .any(|a| a.name == "cautions")
        {
            text("cautions")?.lines().map(String::from).collect()
        } else {
            Vec::new()
        },
    };
    let t = Table {
        pressure,
        flux,
        contact_temperature,
        samples,
        points,
        surfaces,
        info,
    };
    t.check()
        .map_err(|e| Error::Config(format!("{}: {e}", path.display())))?;
    Ok(t)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small synthetic table: 3 pressures × 2 fluxes × 1 temperature × 3
    /// samples, with one failed point and, if `shard`, the paths of shard 0/2 only.
    pub(crate) fn synthetic(shard: Option<Shard>) -> Table {
        let (np, nh, nt, ns) = (3, 2, 1, 3);
        let mut points = Vec::new();
        for ip in 0..np {
            for ih in 0..nh {
                for it in 0..nt {
                    for is in 0..ns {
                        let g = is * nt + it;
                        if shard.is_some_and(|s| !s.owns(g)) {
                            points.push(PointRecord::not_computed());
                        } else if (ip, ih, is) == (2, 1, 1) {
                            points.push(PointRecord::failed("Newton diverged: \"step 3\" ü"));
                        } else {
                            let jump = 10.0 / (1.0 + ip as f64) + 0.1 * is as f64 + ih as f64;
                            points.push(PointRecord::converged(PointValues {
                                jump,
                                conductance: 1e6 * (1 + ih) as f64 / jump,
                                contact_fraction: 0.1 * (1 + ip) as f64,
                                mean_gap: 1e-6 / (1 + ip) as f64,
                                self_consistency_iterations: 3 + is as u32,
                                newton_iterations: 20 + ip as u32,
                                jump_error: (ih == 0).then_some(0.01 * jump),
                                error_target_met: (ih == 0).then_some(is == 0),
                                dofs: 900 + 10 * ip as u32,
                            }));
                        }
                    }
                }
            }
        }
        Table {
            pressure: vec![1e3, 1e4, 1e5],
            flux: vec![1e5, 1e6],
            contact_temperature: vec![293.15],
            samples: ns,
            points,
            surfaces: (0..ns)
                .map(|s| {
                    Some(SampleSurfaces {
                        upper_rms: 5e-7 + 1e-8 * s as f64,
                        lower_rms: 0.0,
                        upper_fit_error: 1e-9,
                        lower_fit_error: 0.0,
                    })
                })
                .collect(),
            info: TableInfo {
                config: "[sweep]\nsamples = 3\n".repeat(5000),
                config_sha256: "ab".repeat(32),
                source: "tables/x.toml".into(),
                seed: 7,
                identification: "two-phase-self-consistent".into(),
                generator: "tcgen test".into(),
                git_revision: "abc".into(),
                created: "2026-01-01T00:00:00Z".into(),
                wall_time: 1.5,
                threads: vec![2],
                shard,
                // Written and read back with and without cautions.
                cautions: match shard {
                    Some(_) => vec!["degree 1 in 3D: a caution".into(), "another".into()],
                    None => Vec::new(),
                },
            },
        }
    }

    #[test]
    fn table_round_trips_through_netcdf4() {
        let dir = std::env::temp_dir().join(format!("tcgen-nc-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for shard in [None, Some(Shard::new(0, 2).unwrap())] {
            let t = synthetic(shard);
            let p = dir.join("t.nc");
            write_table(&t, &p).unwrap();
            let back = read_table(&p).unwrap();
            assert_eq!(back, t);
            // Deterministic bytes.
            assert_eq!(table_to_bytes(&back).unwrap(), std::fs::read(&p).unwrap());
        }
        if let Ok(keep) = std::env::var("TCGEN_KEEP_SYNTHETIC_TABLE") {
            write_table(&synthetic(None), Path::new(&keep)).unwrap();
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn refuses_other_files() {
        let p = std::env::temp_dir().join(format!("tcgen-nc-bad-{}.nc", std::process::id()));
        std::fs::write(&p, b"not a table").unwrap();
        assert!(read_table(&p).is_err());
        std::fs::remove_file(&p).unwrap();
    }
}
