//! The sweep runner: the tasks of a shard in parallel (rayon) — the fluxes
//! of one sample and contact temperature share a solver; with pressure
//! continuation a task runs all pressures of its paths, without it each
//! pressure is a task of its own; adaptive tasks at most as many at once as
//! the memory holds refined levels at `max_dofs`
//! ([`crate::solve::resources::concurrent_paths`]) — a checkpoint line per
//! finished piece, progress, and the table written atomically at the end.

use std::collections::BTreeSet;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::homogenize::path::{LevelObserver, LevelReport};
use crate::io::provenance;
use crate::io::table::{PointRecord, PointStatus, Table, TableInfo};
use crate::sweep::checkpoint::{Checkpoint, Header, checkpoint_path};
use crate::sweep::config::SweepConfig;
use crate::sweep::path::{PathPiece, solve_flux_group};
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
    /// Start no new task after this many tasks in this run (as `deadline`).
    pub max_tasks: Option<usize>,
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
            max_tasks: None,
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
    /// (deadline or task limit): the checkpoint is kept for `--resume`.
    pub table: Option<Table>,
    /// The output file.
    pub output: PathBuf,
    /// Paths of this shard.
    pub shard_paths: usize,
    /// Micro-solves (points) of this shard.
    pub shard_micro_solves: usize,
    /// Micro-solves read back from the checkpoint.
    pub reused_micro_solves: usize,
    /// Micro-solves computed by this run.
    pub micro_solves: usize,
    /// Failed points among those computed by this run.
    pub failed_micro_solves: usize,
    /// Tasks run (a task: the fluxes of one sample and contact temperature,
    /// over all pressures, or over one pressure without continuation).
    pub tasks: usize,
    /// Worker threads.
    pub threads: usize,
    /// Tasks run at once: `threads` (or the tasks, if fewer), or fewer still
    /// for adaptive paths whose refined levels would not fit in memory side
    /// by side ([`crate::solve::resources::concurrent_paths`]).
    pub paths_at_once: usize,
    /// Timing.
    pub timing: Timing,
}

/// Path `k = (s·n_θ + t)·n_h + h` → `(s, t, h)`.
pub fn path_indices(k: usize, nh: usize, nt: usize) -> (usize, usize, usize) {
    (k / (nh * nt), (k / nh) % nt, k % nh)
}

/// The table of a configuration from finished pieces `(path, piece)`; points
/// not given are [`PointStatus::NotComputed`].
pub fn assemble(
    cfg: &SweepConfig,
    pieces: &[(usize, PathPiece)],
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
    let mut sorted: Vec<&(usize, PathPiece)> = pieces.iter().collect();
    sorted.sort_by_key(|(k, o)| (*k, o.from));
    for (k, o) in sorted {
        let (s, it, ih) = path_indices(*k, nh, nt);
        if s >= ns || o.from + o.points.len() > np {
            return Err(Error::Config(format!(
                "path {k} (pressures from {}) does not fit the grid {np}×{nh}×{nt}×{ns}",
                o.from
            )));
        }
        for (j, r) in o.points.iter().enumerate() {
            let i = t.index(o.from + j, ih, it, s);
            t.points[i] = r.clone();
        }
        if t.surfaces[s].is_none() {
            t.surfaces[s] = o.surfaces;
        }
    }
    Ok(t)
}

/// One unit of work: the paths `paths` (fluxes of one sample and contact
/// temperature) over the pressures `pressures`.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Task {
    paths: Vec<usize>,
    pressures: Range<usize>,
}

/// The tasks computing the points `(path, pressure)` that `done` lacks among
/// the `owned` paths: with continuation, each group of paths of one (sample,
/// temperature) over all pressures; without, each group at each pressure.
fn tasks(
    owned: &[usize],
    done: &BTreeSet<(usize, usize)>,
    np: usize,
    nh: usize,
    continuation: bool,
) -> Vec<Task> {
    let mut out: Vec<Task> = Vec::new();
    let ranges: Vec<Range<usize>> = if continuation {
        std::iter::once(0..np).collect()
    } else {
        (0..np).map(|ip| ip..ip + 1).collect()
    };
    for r in ranges {
        for &k in owned {
            if r.clone().all(|ip| done.contains(&(k, ip))) {
                continue;
            }
            match out.last_mut() {
                Some(last) if last.pressures == r && last.paths[0] / nh == k / nh => {
                    last.paths.push(k)
                }
                _ => out.push(Task {
                    paths: vec![k],
                    pressures: r.clone(),
                }),
            }
        }
    }
    out
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
    // Shards own (sample, contact temperature) groups: the fluxes of a group share a solver.
    let owned: Vec<usize> = (0..ns * nt * nh).filter(|&k| shard.owns(k / nh)).collect();
    let header = Header::new(&cfg.sha256, shard, shape);
    let ckpt_path = checkpoint_path(output);
    let (checkpoint, reused) = if ckpt_path.exists() {
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
    for (k, o) in &reused {
        if !owned.contains(k) {
            return Err(Error::Config(format!(
                "{}: path {k} is not in shard {shard}",
                ckpt_path.display()
            )));
        }
        for (j, r) in o.points.iter().enumerate() {
            finished.insert((*k, o.from + j), (r.clone(), o.surfaces));
        }
    }
    // A group counts as done at a pressure only if all its paths are (a kill
    // between the lines of one task leaves a partial group): the shared
    // solver then recomputes the whole group, as in an uninterrupted run.
    for g in owned.iter().map(|k| k / nh).collect::<BTreeSet<_>>() {
        let paths: Vec<usize> = owned.iter().copied().filter(|k| k / nh == g).collect();
        for ip in 0..np {
            if !paths.iter().all(|&k| finished.contains_key(&(k, ip))) {
                for &k in &paths {
                    finished.remove(&(k, ip));
                }
            }
        }
    }
    let done: BTreeSet<(usize, usize)> = finished.keys().copied().collect();
    let reused: Vec<(usize, PathPiece)> = finished
        .into_iter()
        .map(|((k, ip), (r, surfaces))| {
            (
                k,
                PathPiece {
                    from: ip,
                    points: vec![r],
                    surfaces,
                    setup_seconds: 0.0,
                    solve_seconds: 0.0,
                },
            )
        })
        .collect();
    let reused_micro_solves = done.len();
    let todo = tasks(&owned, &done, np, nh, cfg.sweep.continuation);
    let pool = {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(n) = options.threads {
            b = b.num_threads(n);
        }
        b.build()
            .map_err(|e| Error::Config(format!("thread pool: {e}")))?
    };
    let threads = pool.current_num_threads();
    let total: usize = todo.iter().map(|t| t.paths.len() * t.pressures.len()).sum();
    let progress = Arc::new(Progress::new(options.progress, total, options.log_interval));
    let on_level: LevelObserver = {
        let progress = Arc::clone(&progress);
        Arc::new(move |r: &LevelReport| progress.level(r))
    };
    let results: Mutex<Vec<(usize, PathPiece)>> = Mutex::new(Vec::new());
    let first_error: Mutex<Option<Error>> = Mutex::new(None);
    let stop = AtomicBool::new(false);
    let started = AtomicUsize::new(0);
    let checkpoint_time = Mutex::new(0.0);
    let ran = AtomicUsize::new(0);
    // The threads this run keeps busy: at most its pieces left to run.
    let busy = threads.min(todo.len()).max(1);
    let (paths_at_once, _) = crate::solve::resources::concurrent_paths(&cfg.case, busy)?;
    let run_task = |task: &Task| {
        if stop.load(Ordering::SeqCst) || options.deadline.is_some_and(|d| Instant::now() >= d) {
            stop.store(true, Ordering::SeqCst);
            return;
        }
        if let Some(m) = options.max_tasks
            && started.fetch_add(1, Ordering::SeqCst) >= m
        {
            stop.store(true, Ordering::SeqCst);
            return;
        }
        ran.fetch_add(1, Ordering::SeqCst);
        let cases: Vec<_> = task
            .paths
            .iter()
            .map(|&k| {
                let (s, it, ih) = path_indices(k, nh, nt);
                cfg.path_case(s, ih, it)
            })
            .collect();
        let on_point = |r: &PointRecord| progress.point(r.status != PointStatus::Converged);
        let pieces = solve_flux_group(
            &cases,
            task.pressures.clone(),
            cfg.sweep.continuation,
            &on_point,
            Some(&on_level),
        );
        for (&k, o) in task.paths.iter().zip(pieces) {
            let t = Instant::now();
            if let Err(e) = checkpoint.append(k, &o) {
                first_error
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .get_or_insert(e);
                stop.store(true, Ordering::SeqCst);
            }
            *checkpoint_time.lock().unwrap_or_else(|p| p.into_inner()) += t.elapsed().as_secs_f64();
            results
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .push((k, o));
        }
    };
    pool.install(|| {
        if paths_at_once >= busy {
            todo.par_iter().for_each(run_task);
        } else {
            // Adaptive paths whose refined levels would not fit in memory
            // side by side (`concurrent_paths`): a few tasks at a time, each
            // with every worker for its factorizations.
            for some in todo.chunks(paths_at_once) {
                some.par_iter().for_each(run_task);
            }
        }
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
    let micro_solves: usize = new.iter().map(|(_, o)| o.points.len()).sum();
    let failed_micro_solves = new
        .iter()
        .flat_map(|(_, o)| &o.points)
        .filter(|p| p.status != PointStatus::Converged)
        .count();
    let mut report = SweepReport {
        table: None,
        output: output.to_path_buf(),
        shard_paths: owned.len(),
        shard_micro_solves: owned.len() * np,
        reused_micro_solves,
        micro_solves,
        failed_micro_solves,
        tasks: ran.into_inner(),
        threads,
        paths_at_once,
        timing,
    };
    if reused_micro_solves + micro_solves < owned.len() * np {
        report.timing.wall = start.elapsed().as_secs_f64();
        return Ok(report);
    }
    let mut all = reused;
    all.extend(new);
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
        cautions: crate::io::surface_csv::run_cautions(&cfg.path_case(0, 0, 0)),
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
    fn tasks_group_fluxes_and_skip_finished_points() {
        // 2 samples × 1 temperature × 3 fluxes; shard 0/2 owns paths 0, 2, 4.
        let owned = [0, 2, 4];
        let mut done = BTreeSet::new();
        let t = tasks(&owned, &done, 2, 3, true);
        assert_eq!(t.len(), 2);
        assert_eq!(
            (t[0].paths.clone(), t[0].pressures.clone()),
            (vec![0, 2], 0..2)
        );
        assert_eq!(
            (t[1].paths.clone(), t[1].pressures.clone()),
            (vec![4], 0..2)
        );
        done.extend([(0, 0), (0, 1), (2, 0)]);
        let t = tasks(&owned, &done, 2, 3, false);
        let got: Vec<_> = t
            .iter()
            .map(|t| (t.paths.clone(), t.pressures.clone()))
            .collect();
        assert_eq!(got, vec![(vec![4], 0..1), (vec![2], 1..2), (vec![4], 1..2)]);
    }

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
