//! Up-front resource check: the unknowns of a case's micro-sample and the
//! memory its solve needs, estimated before anything is allocated, so that a
//! case that cannot fit is refused with the estimate instead of dying in an
//! allocation (`tcgen check`, `tcgen solve`, `tcgen sweep`).
//!
//! Unknowns: each body is a tensor NURBS patch of degree `p` with `n_i`
//! elements per direction, so `Π (n_i + p)` control points with `d + 1`
//! fields (displacement, temperature), plus the lumped contact multipliers
//! (normal pressure and interface flux) on the slave's `Π (n_lateral + p)`
//! surface control points (`n_x + p` in 2D, `(n_x + p)(n_y + p)` in 3D);
//! interface refinement (`interface_levels`) adds about
//! `4 · 2^(l(d−1)) · Π n_lateral` control points per level `l` (a graded
//! band of two layers; `4 · 2^l · n_x` in 2D).
//!
//! Memory: `B + c · N^1.1 · ((2p + 1)/5)^d`, about linear in the unknowns
//! `N`. The factorizations are LDLᵀ on METIS orderings where the tangent is
//! symmetric (every measured case), large 3D ones in single precision, and beside their factors the bulk quadrature
//! and the assembled tangents hold as much again; so the peak grows about
//! as the unknowns do, not as a fill-in exponent. Fitted on the peak
//! resident memory (`/usr/bin/time`'s KiB × 1024, stop 63, one process per
//! mesh):
//!
//! - 2D (`B` = 5 MB, `c` = 5 100 B): the Sect. 5.7 sample
//!   (`tables/sinusoid_on_flat.toml`, p = 2, its 6-pressure path from 300 Pa
//!   to 100 kPa on fixed meshes of 16 × 8 to 128 × 64 elements): 16 MB,
//!   45 MB, 148 MB and 614 MB at N = 1 008, 3 296, 11 904 and 45 140,
//!   which it reproduces within 10 %.
//! - 3D (`B` = 100 MB, `c` = 12 000 B): the egg box of
//!   `tables/egg_box_on_flat.toml` at 100 kPa on fixed meshes of
//!   `[n, n, n/2]` / `[n−1, n−1, n/2]` elements, n = 8 to 24: 188 MB,
//!   312 MB, 1.05 GB, 1.19 GB and 1.92 GB at N = 4 544, 12 072, 25 168,
//!   45 368 and 74 208 (the model 0.89–1.51 times that); and its adaptive
//!   points at 72 kPa (levels 2–4, 22 752 to 125 776 unknowns on the last
//!   level: 0.86, 2.35 and 5.01 GB) and at 21–132 kPa with the thermal
//!   zone (level 5, 185 424 to 358 352 unknowns: 7.27 to 15.8 GB), where
//!   it is within 8 % (0.92–1.04). The hierarchical levels couple more functions than
//!   a tensor mesh of as many unknowns, so the model is fitted to them and
//!   is an upper estimate for tensor meshes. At p = 3 it gives 1.5 times
//!   the 979 MB measured on `[12, 12, 6]`.
//!
//! The bulk quadrature and the contact points' states grow with the points
//! per element ([`QuadraturePoints`]; since stop 88 the quadrature keeps the
//! basis values and each point's map, by its layout about 0.37 kB per Gauss
//! point at 3D p = 2, instead of the measured 1.1 kB with the gradients, so
//! the model, fitted before, over-estimates the 3D peaks by up to the
//! difference; and since stop 89 symmetric tangents keep their lower
//! triangle only, `bulk::global::Storage::Lower`: at 244 kPa's level 5 of
//! the egg box 7.7 instead of 8.9 GiB): the
//! coefficient `c` is the one fitted at the points above (3D: 3 × 3 × 3 bulk
//! and 4 × 4 interface points, `tables/egg_box_on_flat.toml`'s; 2D: the
//! defaults), plus a share per point beyond them, measured in 3D on a
//! random areal surface's fourth adaptive level (stop 71: 6.30, 8.11 and
//! 9.92 GB with 3/4, 3/8 and 4/8 points, the last the defaults, where the
//! model without these terms gave 0.58 times the peak; now 0.90–0.94), and
//! in 2D on the Sect. 5.7 sample (128 × 64 elements: 528, 655 and 536 MB
//! with 4/8, 6/8 and 4/16 points).
//!
//! Until stop 62 the 3D model was fitted on the coupled four-field LU of
//! `tcgen bench --only solvers3d` (`N^1.46`); it put the fixed `[24, 24,
//! 12]` egg box at 26.2 GB, refused it on a 24 GB machine, and the solve
//! took 1.92 GB.
//!
//! Elsewhere the models are a rough guide (the check refuses what is clearly
//! out of reach, it does not promise that what passes fits exactly).

use crate::sample::Case;
use crate::{Error, Result};

/// Returns the free pages of the allocator's heaps to the system (glibc's
/// `malloc_trim`; elsewhere nothing). Memory freed as many small blocks (the
/// bulk quadrature: a few vectors per element) stays resident otherwise,
/// where a large factorization cannot reuse it: it allocates its factor and
/// workspace as blocks of their own.
pub fn return_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        unsafe extern "C" {
            fn malloc_trim(pad: usize) -> std::ffi::c_int;
        }
        // SAFETY: `malloc_trim` takes no pointer; it only releases free
        // pages of glibc's heaps, whatever the state of the program.
        unsafe {
            malloc_trim(0);
        }
    }
}

/// Fixed part of the model in 2D (process, geometry, small arrays).
const BASE_BYTES: f64 = 5e6;
/// Fixed part of the model in 3D.
const BASE_BYTES_3D: f64 = 100e6;
/// Coefficient of `N^MEMORY_EXPONENT` at p = 2 in 2D.
const BYTES_PER_UNKNOWN: f64 = 5100.0;
/// Coefficient of `N^MEMORY_EXPONENT` at p = 2 in 3D.
const BYTES_PER_UNKNOWN_3D: f64 = 12000.0;
/// Added to [`BYTES_PER_UNKNOWN_3D`] per bulk Gauss point of an element
/// beyond the fitted 27 ([`QuadraturePoints::fitted`]): a random areal
/// surface's fourth adaptive level (142 828 unknowns) took 8.11 GB with
/// 3 × 3 × 3 points and 9.92 GB with 4 × 4 × 4 (stop 71).
const BYTES_PER_BULK_POINT_3D: f64 = 94.0;
/// Added to [`BYTES_PER_UNKNOWN_3D`] per interface point of a slave face
/// element beyond the fitted 16: the same level took 6.30 GB with 4 × 4
/// points (141 836 unknowns) and 8.11 GB with 8 × 8 (stop 71).
const BYTES_PER_INTERFACE_POINT_3D: f64 = 87.0;
/// Added to [`BYTES_PER_UNKNOWN`] per bulk Gauss point of an element beyond
/// the fitted 16: `tables/sinusoid_on_flat.toml` on 128 × 64 / 108 × 56
/// elements (45 140 unknowns) took 528 MB with 4 × 4 points and 655 MB with
/// 6 × 6 (stop 71).
const BYTES_PER_BULK_POINT: f64 = 48.0;
/// Added to [`BYTES_PER_UNKNOWN`] per interface point of a slave face
/// element beyond the fitted 8: the same mesh took 536 MB with 16 (stop 71).
const BYTES_PER_INTERFACE_POINT: f64 = 8.0;
/// Exponent of the unknowns in both dimensions.
const MEMORY_EXPONENT: f64 = 1.1;

/// The estimate for one micro-solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResourceEstimate {
    /// Control points of the upper and lower bodies.
    pub control_points: [usize; 2],
    /// Unknowns: bulk fields and contact multipliers.
    pub unknowns: usize,
    /// Estimated peak memory of one solve (bytes).
    pub memory: f64,
}

/// Gauss points per direction of a case: bulk (`bulk_points`) and per slave
/// face element (`[contact] interface_points`), which set the quadrature's
/// and the contact points' share of the memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuadraturePoints {
    /// Bulk points per direction.
    pub bulk: usize,
    /// Interface points per direction of a slave face element.
    pub interface: usize,
}

impl QuadraturePoints {
    /// The case's points (the bulk default `p + 2`).
    pub fn of(case: &Case) -> Self {
        let d = &case.discretization;
        Self {
            bulk: d
                .bulk_points
                .unwrap_or_else(|| crate::quadrature::default_bulk_points(d.degree)),
            interface: case.contact.interface_points,
        }
    }

    /// The points the model's coefficient was fitted at in dimension `dim`:
    /// `tables/egg_box_on_flat.toml`'s 3 and 4 in 3D, the defaults (`p + 2`
    /// = 4, and 8) of the Sect. 5.7 sample in 2D.
    pub fn fitted(dim: usize) -> Self {
        if dim == 3 {
            Self {
                bulk: 3,
                interface: 4,
            }
        } else {
            Self {
                bulk: 4,
                interface: 8,
            }
        }
    }
}

/// Estimated peak memory (bytes) of a solve with `unknowns` unknowns at
/// degree `p` in dimension `dim` (2 or 3) with `points` (module
/// documentation).
pub fn memory_for(unknowns: usize, degree: usize, dim: usize, points: QuadraturePoints) -> f64 {
    let stencil = ((2 * degree + 1) as f64 / 5.0).powi(dim as i32);
    let (base, c, per_bulk, per_interface) = if dim == 3 {
        (
            BASE_BYTES_3D,
            BYTES_PER_UNKNOWN_3D,
            BYTES_PER_BULK_POINT_3D,
            BYTES_PER_INTERFACE_POINT_3D,
        )
    } else {
        (
            BASE_BYTES,
            BYTES_PER_UNKNOWN,
            BYTES_PER_BULK_POINT,
            BYTES_PER_INTERFACE_POINT,
        )
    };
    let fitted = QuadraturePoints::fitted(dim);
    let count = |n: usize, k: usize| n.pow(k as u32) as f64;
    // Fewer bulk points than fitted save nothing: 2 × 2 × 2 instead of the
    // fitted 3 × 3 × 3 lowered the peak of the benchmark egg box at 6.25 kPa
    // (five levels) by 2 % only (2.64 → 2.59 GB; docs/3d.md, "Stop 97"), where
    // the per-point share, measured before the quadrature stored less per
    // point (stop 88), would take off 15 %.
    let points_term = per_bulk * (count(points.bulk, dim) - count(fitted.bulk, dim)).max(0.0)
        + per_interface * (count(points.interface, dim - 1) - count(fitted.interface, dim - 1));
    // Fewer points than fitted save at most half (the factor stays).
    let c = (c + points_term).max(0.5 * c);
    base + c * stencil * (unknowns as f64).powf(MEMORY_EXPONENT)
}

/// The unknowns and memory of the case's initial mesh (before adaptivity).
pub fn estimate(case: &Case) -> ResourceEstimate {
    let d = &case.discretization;
    let p = d.degree;
    let dim = case.dimension();
    let fields = dim + 1;
    let product = |n: &[usize]| n.iter().map(|&n| n.saturating_add(p)).product::<usize>();
    let mut control_points = [
        product(d.elements_upper.as_slice()),
        product(d.elements_lower.as_slice()),
    ];
    // Interface levels: a graded band of about two layers per level on each
    // body, `2^l` times finer along each lateral direction.
    let lateral_bits = dim - 1;
    for (b, e) in [&d.elements_upper, &d.elements_lower].iter().enumerate() {
        let surface: usize = e.lateral().iter().product();
        control_points[b] += (1..=d.interface_levels)
            .map(|l| 4usize.saturating_mul(surface) << (l * lateral_bits))
            .sum::<usize>();
    }
    // Normal pressure and interface flux on the slave's surface control points.
    let multipliers =
        (2 * product(d.elements_upper.lateral())) << (d.interface_levels * lateral_bits);
    let unknowns = fields * (control_points[0] + control_points[1]) + multipliers;
    ResourceEstimate {
        control_points,
        unknowns,
        memory: memory_for(unknowns, p, dim, QuadraturePoints::of(case)),
    }
}

/// A memory figure of this process from Linux's `/proc/self/status`
/// (bytes; `key` e.g. `"VmRSS:"` resident now, `"VmHWM:"` peak resident),
/// if known.
pub fn process_memory(key: &str) -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Bytes of memory this process may use: `TCGEN_MEMORY_LIMIT` (bytes, or
/// with a suffix K, M, G, T, powers of 1024) if set, else the smaller of the
/// machine's available memory (`MemAvailable` in `/proc/meminfo`) and what
/// its control group leaves ([`cgroup_memory_left`]: a cluster job's
/// `--mem`); `None` where none is known.
pub fn memory_limit() -> Result<Option<f64>> {
    if let Ok(v) = std::env::var("TCGEN_MEMORY_LIMIT") {
        return parse_bytes(&v).map(Some).ok_or_else(|| {
            Error::invalid(
                "TCGEN_MEMORY_LIMIT",
                &v,
                "a number of bytes, optionally with K, M, G or T (e.g. 16G)",
            )
        });
    }
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find_map(|l| l.strip_prefix("MemAvailable:"))
                .and_then(|r| r.trim().strip_suffix("kB"))
                .and_then(|kb| kb.trim().parse::<f64>().ok())
        })
        .map(|kb| kb * 1024.0);
    let group = std::fs::read_to_string("/proc/self/cgroup")
        .ok()
        .and_then(|own| cgroup_memory_left(std::path::Path::new(CGROUP_ROOT), &own));
    Ok(match (available, group) {
        (Some(a), Some(g)) => Some(a.min(g)),
        (a, g) => a.or(g),
    })
}

/// Where the control groups are mounted (`/sys/fs/cgroup`: the unified v2
/// hierarchy, or v1's `memory/` below it).
const CGROUP_ROOT: &str = "/sys/fs/cgroup";

/// Bytes the memory control group of this process still leaves it: the
/// smallest over the group and its ancestors of its limit less its usage
/// (less the inactive file cache, which the kernel reclaims before it
/// kills), as the kernel's out-of-memory killer sees it; `None` where no
/// group has a limit. A batch scheduler (Slurm's `--mem`, a container's
/// limit) enforces its limit there, while `MemAvailable` shows the whole
/// node. `own` is `/proc/self/cgroup`; under `root` the v2 hierarchy
/// (`memory.max`, `memory.current`) or v1's `memory/` (`memory.limit_in_bytes`,
/// `memory.usage_in_bytes`), each `memory.stat` giving the inactive file
/// cache. A group's directory that is not visible (another namespace) is
/// looked for from the mount's root.
pub fn cgroup_memory_left(root: &std::path::Path, own: &str) -> Option<f64> {
    // (hierarchy directory, limit file, usage file, inactive cache key)
    let mut hierarchies = Vec::new();
    for line in own.lines() {
        let mut parts = line.splitn(3, ':');
        let (Some(id), Some(controllers), Some(path)) = (parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let path = path.trim().trim_start_matches('/');
        if id == "0" && controllers.is_empty() {
            hierarchies.push((
                root.to_path_buf(),
                path,
                "memory.max",
                "memory.current",
                "inactive_file",
            ));
        } else if controllers.split(',').any(|c| c == "memory") {
            hierarchies.push((
                root.join("memory"),
                path,
                "memory.limit_in_bytes",
                "memory.usage_in_bytes",
                "total_inactive_file",
            ));
        }
    }
    let read_number = |file: &std::path::Path| -> Option<f64> {
        let text = std::fs::read_to_string(file).ok()?;
        text.trim().parse::<f64>().ok()
    };
    let mut left: Option<f64> = None;
    for (mount, path, limit_file, usage_file, inactive_key) in hierarchies {
        // The group's directory, or the mount's root where it is not there.
        let mut dir = mount.join(path);
        if !dir.is_dir() {
            dir = mount.clone();
        }
        loop {
            // "max" (v2) does not parse; v1's "no limit" is near 2^63.
            if let Some(limit) = read_number(&dir.join(limit_file)).filter(|l| *l < 1e18) {
                let usage = read_number(&dir.join(usage_file)).unwrap_or(0.0);
                let inactive = std::fs::read_to_string(dir.join("memory.stat"))
                    .ok()
                    .and_then(|stat| {
                        stat.lines().find_map(|l| {
                            let (key, value) = l.split_once(' ')?;
                            (key == inactive_key).then(|| value.trim().parse::<f64>().ok())?
                        })
                    })
                    .unwrap_or(0.0);
                let here = (limit - (usage - inactive).max(0.0)).max(0.0);
                left = Some(left.map_or(here, |l| l.min(here)));
            }
            if dir == mount || !dir.pop() || !dir.starts_with(&mount) {
                break;
            }
        }
    }
    left
}

/// Where [`memory_left`] takes its figure from, for messages.
pub const MEMORY_LEFT_SOURCE: &str = "TCGEN_MEMORY_LIMIT less the resident memory if set, else the smaller of the machine's MemAvailable and its control group's limit less its usage";

/// Bytes this process may still allocate: `TCGEN_MEMORY_LIMIT` less its
/// resident memory if set, else [`memory_limit`] (the machine's available
/// memory, or its control group's limit less its usage if smaller); `None`
/// where neither is known.
pub fn memory_left() -> Result<Option<f64>> {
    let limit = memory_limit()?;
    Ok(match std::env::var_os("TCGEN_MEMORY_LIMIT") {
        Some(_) => limit.map(|l| (l - process_memory("VmRSS:").unwrap_or(0) as f64).max(0.0)),
        None => limit,
    })
}

/// Refuses an allocation of `bytes` for `what` that [`memory_left`] cannot
/// hold, with [`Error::OutOfMemory`]: on Linux a large allocation succeeds
/// and the process is killed when its pages are touched, so the sizes known
/// in advance (a factorization's values and workspace, from the symbolic
/// analysis) are checked before they are allocated.
pub fn ensure_memory(what: &str, bytes: usize) -> Result<()> {
    match memory_left()? {
        Some(left) if bytes as f64 > left => Err(Error::OutOfMemory {
            what: what.to_string(),
            needed: bytes as f64,
            left,
        }),
        _ => Ok(()),
    }
}

fn parse_bytes(s: &str) -> Option<f64> {
    let s = s.trim();
    let (num, scale) = match s.char_indices().last()? {
        (i, c) if c.is_ascii_alphabetic() => {
            let k = match c.to_ascii_uppercase() {
                'K' => 1,
                'M' => 2,
                'G' => 3,
                'T' => 4,
                _ => return None,
            };
            (&s[..i], 1024f64.powi(k))
        }
        _ => (s, 1.0),
    };
    num.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && *x > 0.0)
        .map(|x| x * scale)
}

/// Human-readable bytes (kB, MB, GB, TB; powers of 1000).
pub fn format_bytes(b: f64) -> String {
    match b {
        b if b >= 1e12 => format!("{:.1} TB", b / 1e12),
        b if b >= 1e9 => format!("{:.1} GB", b / 1e9),
        b if b >= 1e7 => format!("{:.0} MB", b / 1e6),
        b if b >= 1e6 => format!("{:.1} MB", b / 1e6),
        _ => format!("{:.0} kB", b / 1e3),
    }
}

/// `" (TCGEN_MEMORY_LIMIT)"` where that variable sets [`memory_limit`], for messages.
fn limit_note() -> &'static str {
    if std::env::var_os("TCGEN_MEMORY_LIMIT").is_some() {
        " (TCGEN_MEMORY_LIMIT)"
    } else {
        ""
    }
}

/// The paths a sweep of `case` on `threads` worker threads runs at once:
/// `threads`, but for an adaptive case (`target_error`) at most as many
/// solves at `max_dofs` as the memory limit holds ([`memory_for`],
/// [`memory_limit`]; at least one), with a note saying so where that binds.
///
/// A refined level's factorization and assembly are checked against the
/// memory left as they are built ([`ensure_memory`]), so two paths refining
/// at once where the memory holds one of them would refuse a level of
/// whichever came second, flagged: the table would depend on the timing of
/// the threads. In 3D a refined level's factorization is parallel by itself
/// (a 3D point's levels run one at a time in `tcgen solve` for the same
/// reasons).
pub fn concurrent_paths(case: &Case, threads: usize) -> Result<(usize, Option<String>)> {
    let threads = threads.max(1);
    let d = &case.discretization;
    if d.target_error.is_none() {
        return Ok((threads, None));
    }
    let Some(limit) = memory_limit()? else {
        return Ok((threads, None));
    };
    let per_solve = memory_for(
        d.max_dofs,
        d.degree,
        case.dimension(),
        QuadraturePoints::of(case),
    );
    let fit = ((limit / per_solve).floor() as usize).max(1);
    Ok(if fit < threads {
        (
            fit,
            Some(format!(
                "{fit} path(s) at a time on {threads} threads: adaptive levels grow up to max_dofs = {} unknowns, about {} per solve, {} available{}",
                d.max_dofs,
                format_bytes(per_solve),
                format_bytes(limit),
                limit_note()
            )),
        )
    } else {
        (threads, None)
    })
}

/// Refuses a case whose initial mesh cannot fit `concurrent` solves in the
/// memory limit ([`memory_limit`]); the error names the element keys and
/// gives the estimate.
pub fn check(case: &Case, concurrent: usize) -> Result<ResourceEstimate> {
    let e = estimate(case);
    let Some(limit) = memory_limit()? else {
        return Ok(e);
    };
    let need = e.memory * concurrent.max(1) as f64;
    if need > limit {
        let d = &case.discretization;
        return Err(Error::invalid(
            "discretization.elements_upper / elements_lower",
            format!("{} / {}", d.elements_upper, d.elements_lower),
            format!(
                "a mesh that fits in memory: {} unknowns need about {} per solve{} \
                 (estimate, solve::resources), {} available{}; use fewer elements, \
                 or [discretization] target_error to refine only where needed",
                e.unknowns,
                format_bytes(e.memory),
                if concurrent > 1 {
                    format!(
                        ", {} for {concurrent} concurrent solves (--threads)",
                        format_bytes(need)
                    )
                } else {
                    String::new()
                },
                format_bytes(limit),
                limit_note()
            ),
        ));
    }
    Ok(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unknowns of the Sect. 5.7 meshes (the counts the solver reports)
    /// and the memory model against the peaks measured on their 6-pressure
    /// path (stop 63; the previous model, `68 B · N^1.6`, gives
    /// 3.1 times the 614 MB of 128 × 64, which fails this).
    #[test]
    fn estimate_matches_the_sect_5_7_meshes() {
        let mut case = Case::from_toml(
            "[surface.upper]\nkind = \"flat\"\n[surface.lower]\nkind = \"flat\"\n",
            std::path::Path::new("."),
        )
        .unwrap();
        for (upper, lower, unknowns, measured) in [
            ([16, 8], [14, 7], 972, 16.4e6),
            ([32, 16], [27, 14], 3228, 45.0e6),
            ([64, 32], [54, 28], 11772, 147.9e6),
            ([128, 64], [108, 56], 44880, 614.2e6),
        ] {
            case.discretization.elements_upper = upper.into();
            case.discretization.elements_lower = lower.into();
            let e = estimate(&case);
            // Bulk fields: 3 per control point; multipliers: 2 per slave surface point.
            assert_eq!(e.unknowns - 2 * (upper[0] + 2), unknowns, "{upper:?}");
            let ratio = e.memory / measured;
            assert!((0.85..1.15).contains(&ratio), "{upper:?}: {ratio}");
        }
        // The points per element on the finest mesh's 3-pressure path
        // (stop 71; it peaks below the 6-pressure path above, 528 MB with
        // the defaults): the model keeps its ratio to them.
        let ratio = |bulk, interface, measured: f64| {
            memory_for(45_140, 2, 2, QuadraturePoints { bulk, interface }) / measured
        };
        let defaults = ratio(4, 8, 515_664.0 * 1024.0);
        for (bulk, interface, measured) in [(6, 8, 640_080.0), (4, 16, 523_496.0)] {
            let r = ratio(bulk, interface, measured * 1024.0) / defaults;
            assert!((0.95..1.05).contains(&r), "{bulk} / {interface}: {r}");
        }
    }

    /// 3D: `Π (n_i + p)` control points × 4 fields plus two multipliers per
    /// slave surface control point, and the memory model against the peaks
    /// it was fitted on (stop 63): the egg box on fixed `[n, n, n/2]` /
    /// `[n−1, n−1, n/2]` meshes, 0.89–1.51 times their peaks, and its
    /// adaptive levels, within 8 %. The previous LU model
    /// (`2 030 B · N^1.46`) gives 13.7 times the 1.92 GB of
    /// `[24, 24, 12]` and fails this.
    #[test]
    fn estimate_3d_counts_and_memory() {
        let case = Case::from_toml(
            "[sample]\ndimension = 3\n[surface.upper]\nkind = \"flat\"\n[surface.lower]\nkind = \"flat\"\n\
             [discretization]\nelements_upper = [8, 8, 4]\nelements_lower = [7, 6, 4]\n\
             bulk_points = 3\n[contact]\ninterface_points = 4\n",
            std::path::Path::new("."),
        )
        .unwrap();
        let e = estimate(&case);
        assert_eq!(e.control_points, [10 * 10 * 6, 9 * 8 * 6]);
        assert_eq!(e.unknowns, 4 * (600 + 432) + 2 * 10 * 10);
        let mut refined = case.clone();
        refined.discretization.interface_levels = 1;
        let r = estimate(&refined);
        assert_eq!(r.control_points[0], 600 + 4 * 64 * 4);
        assert_eq!(
            r.unknowns - 4 * (r.control_points[0] + r.control_points[1]),
            2 * 100 * 4
        );
        let kib = 1024.0;
        for (n, unknowns, measured) in [
            (8, 4544, 183_652.0 * kib),
            (12, 12_072, 304_404.0 * kib),
            (16, 25_168, 1_022_520.0 * kib),
            (20, 45_368, 1_165_416.0 * kib),
            (24, 74_208, 1_874_348.0 * kib),
        ] {
            let mut fixed = case.clone();
            fixed.discretization.elements_upper = [n, n, n / 2].into();
            fixed.discretization.elements_lower = [n - 1, n - 1, n / 2].into();
            let e = estimate(&fixed);
            assert_eq!(e.unknowns, unknowns, "{n}");
            let ratio = e.memory / measured;
            assert!((0.85..1.7).contains(&ratio), "fixed {n}: {ratio}");
        }
        // Adaptive levels: the last level's unknowns (the solver's count)
        // and the point's peak.
        for (unknowns, measured) in [
            (22_752, 843_964.0 * kib),
            (57_712, 2_297_696.0 * kib),
            (125_776, 4_888_076.0 * kib),
            (185_424, 7.1e6 * kib),
            (240_784, 9.5e6 * kib),
            (267_760, 11.0e6 * kib),
            (358_352, 15.4e6 * kib),
        ] {
            let ratio = memory_for(unknowns, 2, 3, QuadraturePoints::fitted(3)) / measured;
            assert!((0.9..1.1).contains(&ratio), "adaptive {unknowns}: {ratio}");
        }
        // A random areal surface's fourth adaptive level with the case's
        // points and the defaults (stop 71: RMS 0.5 μm, ℓ 2.5 μm, seed 7,
        // 30 kPa; docs/3d.md "Memory model in 3D"); the model without the
        // points' terms gives 0.58 times the defaults' peak, which fails.
        for (bulk, interface, unknowns, measured) in [
            (3, 4, 141_836, 6_152_256.0 * kib),
            (3, 8, 142_828, 8_106_344.0 * kib),
            (4, 8, 142_828, 9_687_784.0 * kib),
        ] {
            let points = QuadraturePoints { bulk, interface };
            let ratio = memory_for(unknowns, 2, 3, points) / measured;
            assert!((0.85..1.15).contains(&ratio), "{points:?}: {ratio}");
        }
        let mut defaults = case.clone();
        defaults.discretization.bulk_points = None;
        defaults.contact.interface_points = 8;
        assert_eq!(
            QuadraturePoints::of(&defaults),
            QuadraturePoints {
                bulk: 4,
                interface: 8
            }
        );
    }

    /// The control group's limit less its usage (less the inactive file
    /// cache), the smallest over its ancestors, in both hierarchies; no
    /// figure where no group limits memory.
    #[test]
    fn control_group_limits_what_is_left() {
        let root = std::env::temp_dir().join(format!("tcgen-cgroup-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let write = |dir: &str, files: &[(&str, &str)]| {
            let d = root.join(dir);
            std::fs::create_dir_all(&d).unwrap();
            for (name, text) in files {
                std::fs::write(d.join(name), text).unwrap();
            }
        };
        // v2: a Slurm job's limit on the job, none on the root or the step.
        write("", &[("memory.max", "max\n")]);
        write(
            "job_1",
            &[
                ("memory.max", "1000000000\n"),
                ("memory.current", "400000000\n"),
                ("memory.stat", "anon 300000000\ninactive_file 100000000\n"),
            ],
        );
        write(
            "job_1/step_0",
            &[("memory.max", "max\n"), ("memory.current", "5\n")],
        );
        let left = cgroup_memory_left(&root, "0::/job_1/step_0\n");
        assert_eq!(left, Some(7e8));
        // A tighter step: the smallest over the ancestors.
        write(
            "job_1/step_0",
            &[
                ("memory.max", "500000000\n"),
                ("memory.current", "200000000\n"),
            ],
        );
        assert_eq!(cgroup_memory_left(&root, "0::/job_1/step_0\n"), Some(3e8));
        // Usage above the limit leaves nothing, not a negative figure.
        write(
            "job_1/step_0",
            &[
                ("memory.max", "500000000\n"),
                ("memory.current", "900000000\n"),
            ],
        );
        assert_eq!(cgroup_memory_left(&root, "0::/job_1/step_0\n"), Some(0.0));
        // A group not visible here (another namespace): the mount's root.
        write(
            "",
            &[
                ("memory.max", "3000000000\n"),
                ("memory.current", "1000000000\n"),
            ],
        );
        assert_eq!(cgroup_memory_left(&root, "0::/elsewhere/job\n"), Some(2e9));
        // v1: the memory controller's hierarchy, its total_inactive_file.
        let v1 = "12:cpu,cpuacct:/slurm/job\n4:memory:/slurm/uid_0/job_2\n0::/\n";
        std::fs::remove_file(root.join("memory.max")).unwrap();
        write(
            "memory",
            &[("memory.limit_in_bytes", "9223372036854771712\n")],
        );
        write(
            "memory/slurm/uid_0/job_2",
            &[
                ("memory.limit_in_bytes", "600000000\n"),
                ("memory.usage_in_bytes", "250000000\n"),
                ("memory.stat", "cache 1\ntotal_inactive_file 50000000\n"),
            ],
        );
        assert_eq!(cgroup_memory_left(&root, v1), Some(4e8));
        // No limit anywhere (v1's "no limit", v2's "max"): no figure.
        write(
            "memory/slurm/uid_0/job_2",
            &[("memory.limit_in_bytes", "9223372036854771712\n")],
        );
        write("", &[("memory.max", "max\n")]);
        assert_eq!(cgroup_memory_left(&root, v1), None);
        assert_eq!(cgroup_memory_left(&root, "garbage\n"), None);
        std::fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn byte_sizes_parse() {
        assert_eq!(parse_bytes("16G"), Some(16.0 * 1024f64.powi(3)));
        assert_eq!(parse_bytes("1000"), Some(1000.0));
        assert_eq!(parse_bytes(" 1.5 m"), Some(1.5 * 1024f64.powi(2)));
        for bad in ["", "G", "-1G", "12Q", "x"] {
            assert_eq!(parse_bytes(bad), None, "{bad}");
        }
        assert_eq!(format_bytes(1.9e9), "1.9 GB");
        assert_eq!(format_bytes(4.2e7), "42 MB");
        assert_eq!(format_bytes(2.5e6), "2.5 MB");
        assert_eq!(format_bytes(2e5), "200 kB");
    }
}
