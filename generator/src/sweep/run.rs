//! The sweep runner: the paths of a shard in parallel (rayon), pressure
//! continuation within a path, a checkpoint line per finished path, progress,
//! and the table written atomically at the end.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::io::provenance;
use crate::io::table::{PointRecord, PointStatus, Table, TableInfo};
use crate::sweep::checkpoint::{Checkpoint, Header, checkpoint_path};
use crate::sweep::config::SweepConfig;
use crate::sweep::path::{FLUX_GROUPS, PathOutcome, solve_flux_group};
use crate::sweep::progress::{Progress, ProgressMode};
use crate::sweep::shard::Shard;
use crate::{Error, Result};

/// How to run a sweep.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Worker threads (`None`: rayon's default, `RAYON_NUM_THREADS` or the core count).
    pub threads: Option<usize>,
    /// The shard to compute.
    pub shard: Shard,
    /// Continue from the checkpoint beside the output, if there is one.
    pub resume: bool,
    /// Progress display.
    pub progress: ProgressMode,
    /// Interval of the log lines.
    pub log_interval: Duration,
    /// Start no new path after this instant (the run stops with its checkpoint; resume later).
    pub deadline: Option<Instant>,
    /// Start no new path after this many paths finished in this run (as `deadline`).
    pub max_paths: Option<usize>,
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            threads: None,
            shard: Shard::ALL,
            resume: false,
            progress: ProgressMode::Auto,
            log_interval: Duration::from_secs(60),
            deadline: None,
            max_paths: None,
        }
    }
}

/// Where the time went (seconds).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// Model set-up (surfaces, fits, meshes, contact), summed over threads.
    pub setup: f64,
    /// Micro-solves (mechanical and thermal phases), summed over threads.
    pub solve: f64,
    /// Checkpoint appends, summed over threads.
    pub checkpoint: f64,
    /// Writing the table.
    pub write: f64,
    /// Wall time of the run.
    pub wall: f64,
}

/// The result of [`run_sweep`].
#[derive(Clone, Debug)]
pub struct SweepReport {
    /// The table (complete for this shard), or `None` if the run stopped early
    /// (deadline or path limit): the checkpoint is kept for `--resume`.
    pub table: Option<Table>,
    /// The output file.
    pub output: PathBuf,
    /// Paths of this shard.
    pub shard_paths: usize,
    /// Paths read back from the checkpoint.
    pub reused_paths: usize,
    /// Paths computed by this run.
    pub computed_paths: usize,
    /// Micro-solves (points) computed by this run.
    pub micro_solves: usize,
    /// Failed points among those computed by this run.
    pub failed_micro_solves: usize,
    /// Worker threads.
    pub threads: usize,
    /// Timing.
    pub timing: Timing,
}

/// Path `k = (s·n_θ + t)·n_h + h` → `(s, t, h)`.
pub fn path_indices(k: usize, nh: usize, nt: usize) -> (usize, usize, usize) {
    (k / (nh * nt), (k / nh) % nt, k % nh)
}

/// The table of a configuration from finished paths; paths not given are
/// [`PointStatus::NotComputed`].
pub fn assemble(
    cfg: &SweepConfig,
    paths: &[(usize, PathOutcome)],
    info: TableInfo,
) -> Result<Table> {
    let (np, nh, nt, ns) = (
        cfg.pressures.len(),
        cfg.fluxes.len(),
        cfg.contact_temperatures.len(),
        cfg.sweep.samples,
    );
    let mut t = Table {
        pressure: cfg.pressures.clone(),
        flux: cfg.fluxes.clone(),
        contact_temperature: cfg.contact_temperatures.clone(),
        samples: ns,
        points: vec![PointRecord::not_computed(); np * nh * nt * ns],
        surfaces: vec![None; ns],
        info,
    };
    let mut sorted: Vec<&(usize, PathOutcome)> = paths.iter().collect();
    sorted.sort_by_key(|(k, _)| *k);
    for (k, o) in sorted {
        let (s, it, ih) = path_indices(*k, nh, nt);
        if s >= ns || o.points.len() != np {
            return Err(Error::Config(format!(
                "path {k} does not fit the grid {np}×{nh}×{nt}×{ns}"
            )));
        }
        for (ip, r) in o.points.iter().enumerate() {
            let i = t.index(ip, ih, it, s);
            t.points[i] = r.clone();
        }
        if t.surfaces[s].is_none() {
            t.surfaces[s] = o.surfaces;
        }
    }
    Ok(t)
}

/// Runs (or resumes) the shard `options.shard` of a sweep and writes its
/// table to `output` atomically; the checkpoint `<output>.checkpoint` is
/// removed once the table is written.
pub fn run_sweep(cfg: &SweepConfig, output: &Path, options: &SweepOptions) -> Result<SweepReport> {
    let start = Instant::now();
    let (np, nh, nt, ns) = (
        cfg.pressures.len(),
        cfg.fluxes.len(),
        cfg.contact_temperatures.len(),
        cfg.sweep.samples,
    );
    let shape = [np, nh, nt, ns];
    let shard = options.shard;
    let owned: Vec<usize> = (0..ns * nt * nh).filter(|&k| shard.owns(k)).collect();
    let header = Header::new(&cfg.sha256, shard, shape);
    let ckpt_path = checkpoint_path(output);
    let (checkpoint, done) = if ckpt_path.exists() {
        if !options.resume {
            return Err(Error::Config(format!(
                "{} holds the finished work of an interrupted run: continue it with --resume, or delete it to start afresh",
                ckpt_path.display()
            )));
        }
        Checkpoint::resume(&ckpt_path, &header)?
    } else {
        (Checkpoint::create(&ckpt_path, &header)?, Vec::new())
    };
    let mut finished = std::collections::BTreeMap::new();
    for (k, o) in done {
        if !shard.owns(k) || k >= ns * nt * nh {
            return Err(Error::Config(format!(
                "{}: path {k} is not in shard {shard}",
                ckpt_path.display()
            )));
        }
        finished.insert(k, o);
    }
    let reused_paths = finished.len();
    let todo: Vec<usize> = owned
        .iter()
        .copied()
        .filter(|k| !finished.contains_key(k))
        .collect();
    // Tasks: one path each, or the fluxes of one (sample, temperature) together.
    let mut tasks: Vec<Vec<usize>> = Vec::new();
    for &k in &todo {
        match tasks.last_mut() {
            Some(last) if FLUX_GROUPS && last[0] / nh == k / nh => last.push(k),
            _ => tasks.push(vec![k]),
        }
    }
    let pool = {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(n) = options.threads {
            b = b.num_threads(n);
        }
        b.build()
            .map_err(|e| Error::Config(format!("thread pool: {e}")))?
    };
    let threads = pool.current_num_threads();
    let progress = Progress::new(options.progress, todo.len() * np, options.log_interval);
    let results: Mutex<Vec<(usize, PathOutcome)>> = Mutex::new(Vec::new());
    let first_error: Mutex<Option<Error>> = Mutex::new(None);
    let stop = AtomicBool::new(false);
    let started_paths = AtomicUsize::new(0);
    let checkpoint_time = Mutex::new(0.0);
    pool.install(|| {
        tasks.par_iter().for_each(|task| {
            if stop.load(Ordering::SeqCst) || options.deadline.is_some_and(|d| Instant::now() >= d)
            {
                stop.store(true, Ordering::SeqCst);
                return;
            }
            if let Some(m) = options.max_paths
                && started_paths.fetch_add(task.len(), Ordering::SeqCst) >= m
            {
                stop.store(true, Ordering::SeqCst);
                return;
            }
            let cases: Vec<_> = task
                .iter()
                .map(|&k| {
                    let (s, it, ih) = path_indices(k, nh, nt);
                    cfg.path_case(s, ih, it)
                })
                .collect();
            let on_point = |r: &PointRecord| progress.point(r.status != PointStatus::Converged);
            let outcomes = solve_flux_group(&cases, cfg.sweep.continuation, &on_point);
            for (&k, o) in task.iter().zip(outcomes) {
                let t = Instant::now();
                if let Err(e) = checkpoint.append(k, &o) {
                    first_error
                        .lock()
                        .unwrap_or_else(|p| p.into_inner())
                        .get_or_insert(e);
                    stop.store(true, Ordering::SeqCst);
                }
                *checkpoint_time.lock().unwrap_or_else(|p| p.into_inner()) +=
                    t.elapsed().as_secs_f64();
                results
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push((k, o));
            }
        });
    });
    progress.finish();
    if let Some(e) = first_error.into_inner().unwrap_or_else(|p| p.into_inner()) {
        return Err(e);
    }
    let new = results.into_inner().unwrap_or_else(|p| p.into_inner());
    let mut timing = Timing {
        checkpoint: checkpoint_time
            .into_inner()
            .unwrap_or_else(|p| p.into_inner()),
        ..Timing::default()
    };
    for (_, o) in &new {
        timing.setup += o.setup_seconds;
        timing.solve += o.solve_seconds;
    }
    let computed_paths = new.len();
    let micro_solves = computed_paths * np;
    let failed_micro_solves = new
        .iter()
        .flat_map(|(_, o)| &o.points)
        .filter(|p| p.status != PointStatus::Converged)
        .count();
    let mut report = SweepReport {
        table: None,
        output: output.to_path_buf(),
        shard_paths: owned.len(),
        reused_paths,
        computed_paths,
        micro_solves,
        failed_micro_solves,
        threads,
        timing,
    };
    finished.extend(new);
    if finished.len() < owned.len() {
        report.timing.wall = start.elapsed().as_secs_f64();
        return Ok(report);
    }
    let all: Vec<(usize, PathOutcome)> = finished.into_iter().collect();
    let info = TableInfo {
        config: cfg.resolved.clone(),
        config_sha256: cfg.sha256.clone(),
        source: cfg.source.display().to_string(),
        seed: cfg.sweep.seed,
        identification: cfg.identification(),
        generator: provenance::generator(),
        git_revision: provenance::git_revision(),
        created: provenance::utc_now(),
        wall_time: start.elapsed().as_secs_f64(),
        threads: vec![threads as i32],
        shard: (!shard.is_all()).then_some(shard),
    };
    let table = assemble(cfg, &all, info)?;
    let t = Instant::now();
    crate::io::write_table(&table, output)?;
    checkpoint.remove()?;
    report.timing.write = t.elapsed().as_secs_f64();
    report.timing.wall = start.elapsed().as_secs_f64();
    report.table = Some(table);
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_numbering_round_trips() {
        let (nh, nt, ns) = (3, 2, 4);
        let mut k = 0;
        for s in 0..ns {
            for t in 0..nt {
                for h in 0..nh {
                    assert_eq!(path_indices(k, nh, nt), (s, t, h));
                    k += 1;
                }
            }
        }
    }
}
