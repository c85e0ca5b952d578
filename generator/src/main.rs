//! `tcgen`: the command-line interface of the thermal contact resistance generator.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "tcgen",
    version,
    about = "Thermal contact resistance of rough interfaces by computational homogenization (Temizer 2014)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the verification catalogue and print a table (exit status 1 if a check fails).
    Verify {
        /// Print JSON lines instead of a table.
        #[arg(long)]
        json: bool,
        /// Run only the cases whose name contains this text (or any of
        /// several, separated by commas).
        #[arg(long)]
        filter: Option<String>,
        /// List the cases and exit.
        #[arg(long)]
        list: bool,
        /// Also write the data of the plots into DIR: `checks.json` (every
        /// check, and an entry per failed case) and `<case>.csv` per case
        /// that recorded curves (columns `series,x_label,y_label,x,y`).
        #[arg(long, value_name = "DIR")]
        data: Option<std::path::PathBuf>,
    },
    /// Solve one micro-sample along its pressure path (case file: TOML, SI units).
    Solve {
        /// The case file (see schemas/case.md and the examples in tables/).
        case: std::path::PathBuf,
        /// Print one JSON object per pressure instead of a table.
        #[arg(long)]
        json: bool,
        /// Write ParaView files (deformed bodies with displacement, temperature,
        /// Cauchy stress, heat flux; the interface with pressure and flux) into DIR.
        #[arg(long, value_name = "DIR")]
        vtk: Option<std::path::PathBuf>,
        /// Print no progress of the adaptive levels (by default, on standard
        /// error, each level that took a second or more: pressure, level,
        /// unknowns, jump and its estimate, time, how it was solved where
        /// its carried-over state did not converge, peak memory).
        #[arg(long)]
        quiet: bool,
    },
    /// Check a case or sweep file without solving: validate it, print the
    /// resolved configuration with every default, the unknowns, the
    /// estimated memory and how the case mesh fits each rough surface
    /// (exit 2 if invalid or if it cannot fit).
    Check {
        /// A case file (tcgen solve) or a sweep file (tcgen sweep, with [sweep]).
        file: std::path::PathBuf,
        /// Concurrent solves to budget memory for (a sweep's --threads; default:
        /// 1 for a case, RAYON_NUM_THREADS or the cores for a sweep).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Build a table of the macroscopic jump over pressure × flux × contact temperature × samples.
    ///
    /// Exit status: 0 done; 1 a point failed (unless --allow-failures) or an error; 2 a bad
    /// configuration; 3 stopped by --time-limit (finished paths are in the checkpoint: --resume).
    Sweep {
        /// The sweep file: case keys plus [sweep] (see schemas/table.md and tables/).
        config: std::path::PathBuf,
        /// The table to write (netCDF-4); the checkpoint is <OUTPUT>.checkpoint.
        #[arg(short, long)]
        output: std::path::PathBuf,
        /// Continue from the checkpoint of an interrupted run.
        #[arg(long)]
        resume: bool,
        /// Compute shard i of n (0-based, e.g. 0/4); merge the shards with `tcgen merge`.
        #[arg(long)]
        shard: Option<tcgen::sweep::Shard>,
        /// Worker threads (default: RAYON_NUM_THREADS or the number of cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Exit with status 0 even if some points failed (they are masked in the table).
        #[arg(long)]
        allow_failures: bool,
        /// Progress display (auto: a bar on a terminal, log lines otherwise).
        #[arg(long, value_enum, default_value_t = ProgressArg::Auto)]
        progress: ProgressArg,
        /// Seconds between progress log lines.
        #[arg(long, default_value_t = 60.0)]
        log_interval: f64,
        /// Start no new path after this many seconds; finished paths stay in the checkpoint.
        #[arg(long)]
        time_limit: Option<f64>,
    },
    /// Merge the shards of a sweep into the table a single run writes.
    Merge {
        /// The shard tables (any order).
        #[arg(required = true)]
        shards: Vec<std::path::PathBuf>,
        /// The merged table.
        #[arg(short, long)]
        output: std::path::PathBuf,
        /// Exit with status 0 even if some points failed.
        #[arg(long)]
        allow_failures: bool,
    },
    /// Write the surfaces of a case (or of one sample of a sweep) as CSV with their NURBS fit error.
    ///
    /// A 3D case writes one body (--body upper, the default, or lower) on the
    /// points x points grid in the height-map format (one line per y row,
    /// heights in m): its NURBS fit at the case's discretization, or with
    /// --exact the surface itself.
    Surface {
        /// A case file, or a sweep file (its seed; --sample picks the sample).
        case: std::path::PathBuf,
        /// The CSV to write.
        #[arg(short, long)]
        output: std::path::PathBuf,
        /// Sample index of random surfaces (default 0).
        #[arg(long)]
        sample: Option<u64>,
        /// Seed of random surfaces (default: the file's).
        #[arg(long)]
        seed: Option<u64>,
        /// Abscissae per period (3D: grid points per direction; default 1024 in 2D, 256 in 3D).
        #[arg(long)]
        points: Option<usize>,
        /// Which surfaces: both (x,upper,lower,upper_fit,lower_fit) or one (x,z, importable as kind = "profile"); 3D: upper (default) or lower.
        #[arg(long, value_enum, default_value_t = BodyArg::Both)]
        body: BodyArg,
        /// 3D: write the surface's own heights instead of its NURBS fit.
        #[arg(long)]
        exact: bool,
    },
    /// Write the contact law of a table for macroscale codes: an ensemble
    /// statistic of the jump, its spread and its discretization error, the
    /// materials and the extrapolation policy (schemas/law.md).
    Law {
        /// The table (a complete, merged table with every point converged).
        table: std::path::PathBuf,
        /// The output: the law file (schemas/law.md), or the *GAP CONDUCTANCE block with --format calculix|abaqus.
        #[arg(short, long)]
        output: std::path::PathBuf,
        #[command(flatten)]
        args: LawArgs,
    },
    /// Print performance figures of assembly and the sparse solvers.
    Bench {
        /// Approximate numbers of unknowns of the linear-solver benchmark.
        #[arg(long, value_delimiter = ',', default_values_t = vec![20_000usize, 100_000])]
        sizes: Vec<usize>,
        /// Pressures of the micro-sample path benchmark (the Sect. 5.7 sinusoid).
        #[arg(long, default_value_t = 20)]
        pressures: usize,
        /// Run only one part: the linear solvers, the micro-sample path or accuracy per cost.
        #[arg(long, value_enum)]
        only: Option<BenchPart>,
        /// Finest uniform mesh (elements along x) of the accuracy benchmark.
        #[arg(long, default_value_t = 64)]
        finest: usize,
        /// Target error of the effectivity and egg-box benchmarks.
        #[arg(long, default_value_t = 0.01)]
        target: f64,
        /// Refinement levels at most per pressure of the adaptive egg-box benchmark.
        #[arg(long, default_value_t = tcgen::bench::EGG_BOX_BENCH_MAX_LEVELS)]
        max_levels: usize,
        /// Unknowns at most of a level of the adaptive egg-box benchmark
        /// (default: the case's `max_dofs`, 200 000).
        #[arg(long)]
        max_dofs: Option<usize>,
        /// The adaptive egg-box benchmark marking the contact-edge elements'
        /// neighbours on every level (`[discretization] edge_neighbours =
        /// true`; the 3D default marks them on levels 1–2 only).
        #[arg(long)]
        edge_neighbours: bool,
        /// The egg-box benchmark on the case's fixed mesh (refined `--levels`
        /// times at the interface) instead of adaptive to `--target`.
        #[arg(long)]
        fixed: bool,
        /// Elements per direction (even) of the 3D solver benchmark's cubes.
        #[arg(long, value_delimiter = ',', default_values_t = vec![4usize, 8, 12, 16])]
        cube: Vec<usize>,
        /// NURBS degree of the 3D solver benchmark.
        #[arg(long, default_value_t = 2)]
        degree: usize,
        /// Interface refinement levels of the 3D egg-box benchmark with `--fixed`.
        #[arg(long, default_value_t = 0)]
        levels: usize,
        /// Which directions the egg-box benchmark's refinement levels halve
        /// (`[discretization] refinement`).
        #[arg(long, value_enum, default_value = "dyadic")]
        refinement: RefinementArg,
    },
}

/// `[discretization] refinement` on the command line.
#[derive(Clone, Copy, clap::ValueEnum)]
enum RefinementArg {
    /// Every level halves every direction.
    Dyadic,
    /// The lateral directions, then the one through the height, in turn.
    Alternating,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum BenchPart {
    /// Sparse assembly and direct solvers on synthetic grids.
    Solvers,
    /// The Sect. 5.7 micro-sample along a pressure path (fixed mesh and adaptive to 1 %).
    Micro,
    /// Accuracy per cost: uniform against adaptive meshes on the Sect. 5.7 sample.
    Accuracy,
    /// The error estimate's effectivity (estimate / true error) at every point of
    /// the Sect. 5.7 path, Westergaard and the random profile.
    Effectivity,
    /// 3D direct solvers: factorization time and memory versus unknowns (p = 2 cube).
    Solvers3d,
    /// The 3D egg box on a flat along 10 pressures (tables/egg_box_on_flat.toml),
    /// adaptive to `--target` with at most `--max-levels` levels (issue 12's benchmark).
    EggBox,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum ProgressArg {
    Auto,
    Bar,
    Log,
    Quiet,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum BodyArg {
    Both,
    Upper,
    Lower,
}

struct SweepArgs {
    config: std::path::PathBuf,
    output: std::path::PathBuf,
    resume: bool,
    shard: Option<tcgen::sweep::Shard>,
    threads: Option<usize>,
    allow_failures: bool,
    progress: ProgressArg,
    log_interval: f64,
    time_limit: Option<f64>,
}

fn failures_exit(failed: usize, allow: bool) -> ExitCode {
    if failed == 0 || allow {
        ExitCode::SUCCESS
    } else {
        eprintln!("{failed} point(s) failed (masked in the table); --allow-failures accepts them");
        ExitCode::FAILURE
    }
}

/// The cautions of a run of `case` ([`tcgen::io::surface_csv::run_cautions`])
/// on stderr, before it starts.
fn print_cautions(case: &tcgen::sample::Case) {
    for c in tcgen::io::surface_csv::run_cautions(case) {
        eprintln!("caution: {c}");
    }
}

fn sweep(a: SweepArgs) -> ExitCode {
    use tcgen::sweep::{ProgressMode, Shard, SweepConfig, SweepOptions, run_sweep};
    let cfg = match SweepConfig::read(&a.config) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    print_cautions(&cfg.path_case(0, 0, 0));
    // Before any computing: the mesh fits in memory on every path run at once.
    let threads = a.threads.unwrap_or_else(rayon::current_num_threads);
    let busy = cfg.busy_threads(threads);
    let at_once = match tcgen::solve::resources::concurrent_paths(&cfg.case, busy) {
        Ok((n, note)) => {
            if let Some(note) = note {
                eprintln!("note: {note}");
            }
            n
        }
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    if let Err(e) = tcgen::solve::resources::check(&cfg.case, at_once) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    // Before any computing: the table is written to a file.
    if a.output.is_dir() {
        eprintln!(
            "error: invalid input `--output` = {}: a directory; expected the path of the table file to write",
            a.output.display()
        );
        return ExitCode::from(2);
    }
    let start = std::time::Instant::now();
    let options = SweepOptions {
        threads: a.threads,
        shard: a.shard.unwrap_or(Shard::ALL),
        resume: a.resume,
        progress: match a.progress {
            ProgressArg::Auto => ProgressMode::Auto,
            ProgressArg::Bar => ProgressMode::Bar,
            ProgressArg::Log => ProgressMode::Log,
            ProgressArg::Quiet => ProgressMode::Quiet,
        },
        log_interval: std::time::Duration::from_secs_f64(a.log_interval.max(0.0)),
        deadline: a
            .time_limit
            .map(|s| start + std::time::Duration::from_secs_f64(s.max(0.0))),
        max_tasks: None,
    };
    let (np, nh, nt, ns) = (
        cfg.pressures.len(),
        cfg.fluxes.len(),
        cfg.contact_temperatures.len(),
        cfg.sweep.samples,
    );
    println!(
        "tcgen sweep {} -> {}: {np} pressures x {nh} fluxes x {nt} contact temperatures x {ns} samples = {} micro-solves (shard {})",
        a.config.display(),
        a.output.display(),
        np * nh * nt * ns,
        options.shard
    );
    let r = match run_sweep(&cfg, &a.output, &options) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let t = &r.timing;
    println!(
        "  {} of {} micro-solves computed ({} failed) in {} tasks on {} threads{} in {:.1} s: {:.3} micro-solves/s; {} reused from the checkpoint",
        r.micro_solves,
        r.shard_micro_solves,
        r.failed_micro_solves,
        r.tasks,
        r.threads,
        if r.paths_at_once < r.threads.min(r.tasks) {
            format!(" ({} at a time)", r.paths_at_once)
        } else {
            String::new()
        },
        t.wall,
        r.micro_solves as f64 / t.wall.max(1e-9),
        r.reused_micro_solves
    );
    println!(
        "  time: set-up {:.2} s, micro-solves {:.2} s (thread-seconds), checkpoint {:.3} s, table write {:.3} s",
        t.setup, t.solve, t.checkpoint, t.write
    );
    match r.table {
        None => {
            println!(
                "  stopped by --time-limit: {} micro-solves remain; continue with --resume",
                r.shard_micro_solves - r.reused_micro_solves - r.micro_solves
            );
            ExitCode::from(3)
        }
        Some(table) => {
            let failed = table.count(tcgen::io::PointStatus::Failed);
            println!(
                "  wrote {}: {} converged, {failed} failed points",
                a.output.display(),
                table.count(tcgen::io::PointStatus::Converged)
            );
            failures_exit(failed, a.allow_failures)
        }
    }
}

fn merge(shards: &[std::path::PathBuf], output: &std::path::Path, allow: bool) -> ExitCode {
    let result = (|| -> tcgen::Result<tcgen::io::Table> {
        let tables = shards
            .iter()
            .map(|p| tcgen::io::read_table(p))
            .collect::<tcgen::Result<Vec<_>>>()?;
        let t = tcgen::sweep::merge_tables(&tables)?;
        tcgen::io::write_table(&t, output)?;
        Ok(t)
    })();
    match result {
        Ok(t) => {
            let failed = t.count(tcgen::io::PointStatus::Failed);
            println!(
                "merged {} shards into {}: {} converged, {failed} failed points",
                shards.len(),
                output.display(),
                t.count(tcgen::io::PointStatus::Converged)
            );
            failures_exit(failed, allow)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The options of `tcgen surface` other than the paths.
struct SurfaceArgs {
    sample: Option<u64>,
    seed: Option<u64>,
    points: Option<usize>,
    body: BodyArg,
    exact: bool,
}

/// `tcgen surface` on a 3D case: one body's height map.
fn surface_3d(
    case: &tcgen::sample::Case,
    output: &std::path::Path,
    a: &SurfaceArgs,
) -> tcgen::Result<()> {
    use tcgen::io::surface_csv::{export_heightmap, write_heightmap_csv};
    let points = a.points.unwrap_or(256);
    let body = usize::from(matches!(a.body, BodyArg::Lower));
    let e = export_heightmap(case, points, body, !a.exact)?;
    write_heightmap_csv(&e, output)?;
    let d = &case.discretization;
    for (b, (name, n)) in [("upper", &d.elements_upper), ("lower", &d.elements_lower)]
        .into_iter()
        .enumerate()
    {
        println!(
            "{name}: rms {:.4e} m; NURBS fit ({} x {} elements, degree {}) error max {:.3e} m, rms {:.3e} m",
            e.rms[b],
            n.along(0),
            n.along(1),
            d.degree,
            e.fit_max_error[b],
            e.fit_rms_error[b]
        );
    }
    println!(
        "wrote {}: the {} surface{} on a {points} x {points} grid (height map: one line per y row, m)",
        output.display(),
        ["upper", "lower"][body],
        if a.exact { "" } else { "'s NURBS fit" }
    );
    Ok(())
}

fn surface(path: &std::path::Path, output: &std::path::Path, a: &SurfaceArgs) -> ExitCode {
    use tcgen::io::surface_csv::{Bodies, export_surfaces, write_surface_csv};
    let (sample, seed, body) = (a.sample, a.seed, a.body);
    let result = (|| -> tcgen::Result<()> {
        let text = tcgen::error::read_text(path)?;
        let is_sweep = toml::from_str::<toml::Table>(&text)
            .map(|t| t.contains_key("sweep"))
            .unwrap_or(false);
        let mut case = if is_sweep {
            tcgen::sweep::SweepConfig::read(path)?.path_case(0, 0, 0)
        } else {
            tcgen::sample::Case::read(path)?
        };
        for s in [&mut case.surface.upper, &mut case.surface.lower] {
            if let Some(r) = s.random_mut() {
                if let Some(k) = sample {
                    r.sample = Some(k);
                }
                if let Some(k) = seed {
                    r.seed = Some(k);
                }
            }
        }
        if case.dimension() == 3 {
            return surface_3d(&case, output, a);
        }
        if a.exact {
            return Err(tcgen::Error::invalid(
                "--exact",
                "given",
                "absent for a 2D case (its CSV holds the surfaces and their fits)",
            ));
        }
        let points = a.points.unwrap_or(1024);
        let e = export_surfaces(&case, points)?;
        let bodies = match body {
            BodyArg::Both => Bodies::Both,
            BodyArg::Upper => Bodies::Upper,
            BodyArg::Lower => Bodies::Lower,
        };
        write_surface_csv(&e, bodies, output)?;
        for (b, name) in [(0, "upper"), (1, "lower")] {
            println!(
                "{name}: rms {:.4e} m; NURBS fit ({} elements, degree {}) error max {:.3e} m, rms {:.3e} m",
                e.rms[b],
                if b == 0 {
                    case.discretization.elements_upper.along(0)
                } else {
                    case.discretization.elements_lower.along(0)
                },
                case.discretization.degree,
                e.fit_max_error[b],
                e.fit_rms_error[b]
            );
        }
        println!("wrote {} ({points} points)", output.display());
        Ok(())
    })();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// The options of `tcgen law` other than the paths.
#[derive(clap::Args)]
struct LawArgs {
    /// The ensemble statistic the law tabulates (its conductance is |h|/jump
    /// of it): mean-jump (harmonic mean of the conductances),
    /// mean-conductance, or quantile:P (P in 1..=99, percent of the jump; high P is conservative).
    #[arg(long, default_value = "mean-jump")]
    statistic: String,
    /// Extrapolation outside the table: POLICY (every axis) or AXIS=POLICY
    /// (AXIS: pressure, flux, contact_temperature; POLICY: error, clamp,
    /// linear, power = k ∝ p^m from the end cells, pressure only).
    /// Repeatable, applied in order. Default: error on every axis.
    #[arg(long, value_name = "[AXIS=]POLICY")]
    extrapolate: Vec<String>,
    /// Output format: tclaw (the binary law for lookup/, default), calculix
    /// or abaqus (a *GAP CONDUCTANCE block: conductance |h|/jump versus
    /// contact pressure at each contact temperature, for one flux).
    #[arg(long, default_value = "tclaw")]
    format: String,
    /// calculix/abaqus: the flux |h| in W/m^2 (a table node, or inside the
    /// table: interpolated by the law); required if the table has several.
    #[arg(long)]
    flux: Option<f64>,
    /// calculix/abaqus: the deck's unit system, SI (default) or mm-N-s-K
    /// (pressure N/mm^2, conductance mW/(mm^2 K)).
    #[arg(long, default_value = "SI")]
    units: String,
    /// calculix/abaqus: temperatures in degrees Celsius instead of K.
    #[arg(long)]
    celsius: bool,
    /// calculix/abaqus: largest relative deviation of the solver's linear
    /// interpolation of the rows from the law (pressures are inserted).
    #[arg(long, default_value_t = 1e-3)]
    tolerance: f64,
    /// calculix/abaqus: pressures in Pa the rows span (default: the
    /// table's); beyond the table only with --extrapolate pressure=POLICY.
    #[arg(long, value_name = "LO:HI")]
    pressure_range: Option<String>,
}

/// Exit status of a failed `tcgen law`: 2 for bad input, else 1.
fn law_failure(e: &tcgen::Error) -> ExitCode {
    eprintln!("error: {e}");
    match e {
        tcgen::Error::InvalidInput { .. } => ExitCode::from(2),
        _ => ExitCode::FAILURE,
    }
}

fn law(table: &std::path::Path, output: &std::path::Path, a: &LawArgs) -> ExitCode {
    use tcgen::io::{GapConductanceOptions, LawFormat};
    let options =
        (|| -> tcgen::Result<(tcgen::io::LawOptions, LawFormat, GapConductanceOptions)> {
            let mut o = tcgen::io::LawOptions {
                statistic: a.statistic.parse()?,
                ..Default::default()
            };
            for e in &a.extrapolate {
                tcgen::io::apply_extrapolation(&mut o.extrapolation, e)?;
            }
            let format: LawFormat = a.format.parse()?;
            let deck = match format {
                LawFormat::Deck(deck) => deck,
                LawFormat::Tclaw => {
                    let given = [
                        ("--flux", a.flux.is_some()),
                        ("--units", a.units != "SI"),
                        ("--celsius", a.celsius),
                        ("--tolerance", a.tolerance != 1e-3),
                        ("--pressure-range", a.pressure_range.is_some()),
                    ];
                    if let Some((name, _)) = given.iter().find(|(_, g)| *g) {
                        return Err(tcgen::Error::invalid(
                            *name,
                            "given",
                            "only with --format calculix or --format abaqus (a tclaw law holds every flux and pressure)",
                        ));
                    }
                    tcgen::io::GapDeck::Calculix
                }
            };
            let g = GapConductanceOptions {
                deck,
                units: a.units.parse()?,
                celsius: a.celsius,
                flux: a.flux,
                tolerance: a.tolerance,
                pressure_range: a
                    .pressure_range
                    .as_deref()
                    .map(tcgen::io::gap_conductance::parse_pressure_range)
                    .transpose()?,
            };
            g.validate()?;
            Ok((o, format, g))
        })();
    let (options, format, deck) = match options {
        Ok(o) => o,
        Err(e) => return law_failure(&e),
    };
    if let LawFormat::Deck(d) = format {
        return match tcgen::io::write_gap_conductance(table, output, &options, &deck) {
            Ok(rows) => {
                println!(
                    "wrote {}: {} for {} ({} units), |h| = {:e} W/m^2: {} pressures x {} temperature(s), \
                     linear interpolation within {:.2e} of the law (tolerance {:.1e})",
                    output.display(),
                    d.keyword_line(),
                    d.solver(),
                    deck.units.name(),
                    rows.flux,
                    rows.pressures.len(),
                    rows.temperatures.len(),
                    rows.max_deviation,
                    rows.tolerance
                );
                if options.extrapolation.pressure == lookup::Extrapolation::Error {
                    println!(
                        "  outside [{:e}, {:e}] Pa {}: keep contact pressures inside \
                         (or --extrapolate pressure=clamp|power --pressure-range LO:HI)",
                        rows.pressures[0],
                        rows.pressures[rows.pressures.len() - 1],
                        d.outside_rows()
                    );
                }
                ExitCode::SUCCESS
            }
            Err(e) => law_failure(&e),
        };
    }
    match tcgen::io::write_law(table, output, &options) {
        Ok(l) => {
            let a = l.axes();
            let info = l.info();
            let statistic = tcgen::io::describe_statistic(info.statistic);
            println!(
                "wrote {}: {} pressures x {} fluxes x {} contact temperatures, {statistic}",
                output.display(),
                a.pressure.len(),
                a.flux.len(),
                a.contact_temperature.len(),
            );
            let policy = lookup::Axis::ALL
                .map(|x| format!("{} {}", x.name(), info.extrapolation.get(x)))
                .join(", ");
            println!(
                "  discretization error {}; materials recorded; extrapolation: {policy}",
                if l.error_estimated() {
                    let rel = l
                        .jump_error()
                        .iter()
                        .zip(l.jump_mean())
                        .filter(|(_, m)| **m > 0.0)
                        .map(|(e, m)| e / m)
                        .fold(0.0, f64::max);
                    format!("estimated (at most {:.2} % of the jump)", 100.0 * rel)
                } else {
                    "not estimated (table built without [discretization] target_error)".into()
                }
            );
            for x in lookup::Axis::ALL {
                let nodes = a.get(x);
                if nodes.len() == 1 && info.extrapolation.get(x) == lookup::Extrapolation::Error {
                    println!(
                        "  note: one {} node ({}): every other value is outside the table \
                         (--extrapolate {}=clamp makes the law constant along it)",
                        x.name(),
                        nodes[0],
                        x.name()
                    );
                }
            }
            ExitCode::SUCCESS
        }
        Err(e) => law_failure(&e),
    }
}

fn check(file: &std::path::Path, threads: Option<usize>) -> ExitCode {
    use tcgen::solve::resources::{self, format_bytes};
    let text = match std::fs::read_to_string(file) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {}: {e}", file.display());
            return ExitCode::from(2);
        }
    };
    let is_sweep = toml::from_str::<toml::Table>(&text).is_ok_and(|t| t.contains_key("sweep"));
    let mut paths_note = None;
    let loaded = if is_sweep {
        tcgen::sweep::SweepConfig::read(file).and_then(|c| {
            let n = c.busy_threads(threads.unwrap_or_else(rayon::current_num_threads));
            let (at_once, note) = resources::concurrent_paths(&c.case, n)?;
            paths_note = note;
            let sample0 = Some(c.path_case(0, 0, 0));
            Ok((
                c.case.clone(),
                c.resolved.clone(),
                at_once,
                "sweep",
                sample0,
            ))
        })
    } else {
        tcgen::sample::Case::read(file).and_then(|c| {
            let resolved = tcgen::sweep::config::resolved_case(&c)?;
            Ok((c, resolved, threads.unwrap_or(1), "case", None))
        })
    };
    let (case, resolved, concurrent, kind, sample0) = match loaded {
        Ok(x) => x,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    println!(
        "# {}: a valid {kind} file. Resolved configuration (every default explicit):\n",
        file.display()
    );
    println!("{resolved}");
    let e = resources::estimate(&case);
    let d = &case.discretization;
    let dim = case.dimension();
    println!(
        "# dimension {dim}: elements upper {}, lower {} ({})",
        d.elements_upper,
        d.elements_lower,
        if dim == 3 { "[nx, ny, nz]" } else { "[nx, nz]" }
    );
    println!(
        "# unknowns: {} (upper body {} and lower body {} control points x {} fields, contact multipliers)",
        e.unknowns,
        e.control_points[0],
        e.control_points[1],
        dim + 1
    );
    println!(
        "# estimated memory: {} per solve{}",
        format_bytes(e.memory),
        if concurrent > 1 {
            format!(
                ", {} for {concurrent} concurrent solves",
                format_bytes(e.memory * concurrent as f64)
            )
        } else {
            String::new()
        }
    );
    if d.target_error.is_some() {
        println!(
            "# adaptive (target_error {}), marking {}{}: meshes grow up to max_dofs = {} unknowns, about {} per solve at that size; Newton's relative tolerance {:.0e} (at least {:.0e} · target_error)",
            d.target_error.unwrap_or_default(),
            d.edge_marks_in(dim),
            d.refinement.clause(),
            d.max_dofs,
            format_bytes(resources::memory_for(
                d.max_dofs,
                d.degree,
                dim,
                resources::QuadraturePoints::of(&case)
            )),
            tcgen::homogenize::path::newton_settings(&case).relative_tolerance,
            tcgen::homogenize::path::newton_target_share(case.dimension())
        );
    }
    // The 3D cases the project ships integrate with the points the memory
    // model was fitted at (docs/3d.md, "Stop 87"); a p = 2 case with more
    // learns what they cost.
    let points = resources::QuadraturePoints::of(&case);
    let shipped = resources::QuadraturePoints::fitted(dim);
    if dim == 3
        && d.degree == 2
        && (points.bulk > shipped.bulk || points.interface > shipped.interface)
    {
        let at = if d.target_error.is_some() {
            d.max_dofs
        } else {
            e.unknowns
        };
        println!(
            "# quadrature: {b}^3 bulk and {i} x {i} interface points per element; the shipped 3D cases use bulk_points = {} and [contact] interface_points = {} (about {} instead of {} per solve at {at} unknowns, and half the time of the defaults on tables/demo_3d.toml, its jumps within 2e-4: docs/3d.md, \"Stop 87\")",
            shipped.bulk,
            shipped.interface,
            format_bytes(resources::memory_for(at, d.degree, dim, shipped)),
            format_bytes(resources::memory_for(at, d.degree, dim, points)),
            b = points.bulk,
            i = points.interface,
        );
    }
    if let Some(note) = paths_note {
        println!("# {note}");
    }
    // The surfaces as the case mesh fits them (a sweep's sample 0).
    let surfaces_case = sample0.as_ref().unwrap_or(&case);
    let fits = match tcgen::io::surface_csv::CaseFits::of(surfaces_case) {
        Ok(f) => f,
        Err(err) => {
            eprintln!("error: {err}");
            return ExitCode::from(2);
        }
    };
    let random = [&surfaces_case.surface.upper, &surfaces_case.surface.lower]
        .iter()
        .any(|s| s.random().is_some());
    let sample = if is_sweep && random {
        " (sample 0)"
    } else {
        ""
    };
    match fits.describe(surfaces_case) {
        Ok(lines) => lines.iter().for_each(|l| println!("# {l}{sample}")),
        Err(err) => {
            eprintln!("error: {err}");
            return ExitCode::from(2);
        }
    }
    for c in tcgen::io::surface_csv::run_cautions_with(&case, Some(&fits)) {
        println!("# caution: {c}");
    }
    match resources::memory_limit() {
        Ok(Some(limit)) => println!("# memory available: {}", format_bytes(limit)),
        Ok(None) => println!("# memory available: unknown (set TCGEN_MEMORY_LIMIT)"),
        Err(err) => {
            eprintln!("error: {err}");
            return ExitCode::from(2);
        }
    }
    match resources::check(&case, concurrent) {
        Ok(_) => {
            println!("# ok");
            ExitCode::SUCCESS
        }
        Err(err) => {
            eprintln!("error: {err}");
            ExitCode::from(2)
        }
    }
}

fn verify(
    json: bool,
    filter: Option<String>,
    list: bool,
    data: Option<&std::path::Path>,
) -> ExitCode {
    let cases: Vec<_> = tcgen::verify::catalogue()
        .into_iter()
        .filter(|c| {
            filter
                .as_deref()
                .is_none_or(|f| f.split(',').any(|f| c.name.contains(f.trim())))
        })
        .collect();
    if list {
        for c in &cases {
            println!("{:<28} {}", c.name, c.description);
        }
        return ExitCode::SUCCESS;
    }
    let mut all = Vec::new();
    let mut errors = Vec::new();
    let mut failed = 0;
    tcgen::verify::take_series();
    for c in &cases {
        let t = std::time::Instant::now();
        match (c.run)() {
            Ok(checks) => {
                if json {
                    for ch in &checks {
                        println!("{}", serde_json::to_string(ch).expect("serializable"));
                    }
                } else {
                    eprintln!("{:<28} {:>7.2} s", c.name, t.elapsed().as_secs_f64());
                }
                failed += checks.iter().filter(|c| !c.pass).count();
                all.extend(checks);
            }
            Err(e) => {
                failed += 1;
                let entry =
                    serde_json::json!({"case": c.name, "error": e.to_string(), "pass": false});
                if json {
                    println!("{entry}");
                } else {
                    eprintln!("{:<28} ERROR: {e}", c.name);
                }
                errors.push(entry);
            }
        }
    }
    if let Some(dir) = data
        && let Err(e) = write_verify_data(dir, &all, errors)
    {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    if !json {
        print!("{}", tcgen::verify::format_table(&all));
        println!(
            "{} passed, {} failed",
            all.iter().filter(|c| c.pass).count(),
            failed
        );
    }
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// One CSV field (quoted when it holds a comma, quote or newline).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// `tcgen verify --data DIR`: `checks.json` and one `<case>.csv` per case
/// with recorded series (rows `series,x_label,y_label,x,y`, in recording order).
fn write_verify_data(
    dir: &std::path::Path,
    checks: &[tcgen::verify::Check],
    errors: Vec<serde_json::Value>,
) -> tcgen::Result<()> {
    let io = |path: &std::path::Path| {
        let path = path.display().to_string();
        move |source| tcgen::Error::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let mut entries: Vec<serde_json::Value> = checks
        .iter()
        .map(|c| serde_json::to_value(c).expect("serializable"))
        .collect();
    entries.extend(errors);
    let path = dir.join("checks.json");
    let text = serde_json::to_string_pretty(&entries).expect("serializable");
    std::fs::write(&path, text + "\n").map_err(io(&path))?;
    let mut files: Vec<(String, String)> = Vec::new();
    for s in tcgen::verify::take_series() {
        let i = match files.iter().position(|(c, _)| *c == s.case) {
            Some(i) => i,
            None => {
                files.push((s.case.clone(), "series,x_label,y_label,x,y\n".into()));
                files.len() - 1
            }
        };
        let (name, xl, yl) = (
            csv_field(&s.name),
            csv_field(&s.x_label),
            csv_field(&s.y_label),
        );
        for (x, y) in s.x.iter().zip(&s.y) {
            files[i]
                .1
                .push_str(&format!("{name},{xl},{yl},{x:e},{y:e}\n"));
        }
    }
    for (case, text) in files {
        let path = dir.join(format!("{case}.csv"));
        std::fs::write(&path, text).map_err(io(&path))?;
    }
    Ok(())
}

/// `tcgen solve` prints an adaptive level's progress line when it took this
/// long (s): the levels of 2D points take milliseconds, 3D ones minutes.
const SOLVE_LEVEL_LINE_SECONDS: f64 = 1.0;

fn solve(
    path: &std::path::Path,
    json: bool,
    vtk: Option<std::path::PathBuf>,
    quiet: bool,
) -> ExitCode {
    let case = match tcgen::sample::Case::read(path) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    print_cautions(&case);
    if let Err(e) = tcgen::solve::resources::check(&case, 1) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    if let Some(dir) = &vtk
        && dir.exists()
        && !dir.is_dir()
    {
        eprintln!(
            "error: invalid input `--vtk` = {}: an existing file; expected a directory (created if missing)",
            dir.display()
        );
        return ExitCode::from(2);
    }
    // The lateral offset of the upper body only when its top face slides.
    let sliding = case.sample.top_lateral == tcgen::sample::case::TopLateral::Free;
    let sliding_y = sliding && case.dimension() == 3;
    // The error estimate, unknowns and levels of the adaptive meshes.
    let adaptive = case.discretization.target_error.is_some();
    if !json {
        println!(
            "{:>12} {:>9} {:>12} {:>12}{} {:>12}{} {:>12} {:>6} {:>6}  status",
            "pressure/Pa",
            "contact",
            "mean_gap/m",
            "approach/m",
            match (sliding, sliding_y) {
                (true, true) => format!(" {:>12} {:>12}", "offset/m", "offset_y/m"),
                (true, false) => format!(" {:>12}", "offset/m"),
                _ => String::new(),
            },
            "jump/K",
            if adaptive {
                format!(" {:>9} {:>7} {:>7}", "error/K", "dofs", "levels")
            } else {
                String::new()
            },
            "k/(W/m2K)",
            "newton",
            "sc"
        );
    }
    let t = std::time::Instant::now();
    // The adaptive levels that take a while, as they end (3D points take
    // minutes per level, and their rows come after the last).
    let levels: Option<tcgen::homogenize::LevelObserver> = (adaptive && !quiet).then(|| {
        std::sync::Arc::new(|r: &tcgen::homogenize::LevelReport| {
            if r.seconds >= SOLVE_LEVEL_LINE_SECONDS {
                eprintln!("  {r}");
            }
        }) as tcgen::homogenize::LevelObserver
    });
    let result = tcgen::homogenize::solve_case_observed(
        &case,
        vtk,
        |r| {
            if json {
                println!("{}", serde_json::to_string(r).expect("serializable"));
            } else {
                let status = match (&r.status, r.error_target_met) {
                    (tcgen::homogenize::Status::Converged, Some(false)) => format!(
                        "converged, error target NOT met ({})",
                        r.refinement_stop.as_deref().unwrap_or("refinement stopped")
                    ),
                    (tcgen::homogenize::Status::Converged, _) => "converged".to_string(),
                    (tcgen::homogenize::Status::Failed(m), _) => format!("FAILED: {m}"),
                };
                println!(
                    "{:>12.4e} {:>9.4} {:>12.4e} {:>12.4e}{} {:>12.6e}{} {:>12.4e} {:>6} {:>6}  {status}",
                    r.pressure,
                    r.interface.contact_fraction,
                    r.interface.mean_gap,
                    r.interface.approach,
                    match (sliding, sliding_y) {
                        (true, true) => format!(
                            " {:>12.4e} {:>12.4e}",
                            r.interface.lateral_offset, r.interface.lateral_offset_y
                        ),
                        (true, false) => format!(" {:>12.4e}", r.interface.lateral_offset),
                        _ => String::new(),
                    },
                    r.jump,
                    if adaptive {
                        format!(
                            " {:>9} {:>7} {:>7}",
                            r.jump_error.map_or("-".into(), |e| format!("{e:.2e}")),
                            r.dofs,
                            format!("{}/{}", r.levels[1], r.levels[0])
                        )
                    } else {
                        String::new()
                    },
                    r.conductance,
                    r.newton_iterations,
                    r.self_consistency_iterations
                );
            }
        },
        levels,
    );
    match result {
        Ok(points) => {
            if !json {
                eprintln!(
                    "{} points in {:.2} s",
                    points.len(),
                    t.elapsed().as_secs_f64()
                );
            }
            if points.iter().all(|p| p.converged) {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Verify {
            json,
            filter,
            list,
            data,
        } => verify(json, filter, list, data.as_deref()),
        Command::Solve {
            case,
            json,
            vtk,
            quiet,
        } => solve(&case, json, vtk, quiet),
        Command::Sweep {
            config,
            output,
            resume,
            shard,
            threads,
            allow_failures,
            progress,
            log_interval,
            time_limit,
        } => sweep(SweepArgs {
            config,
            output,
            resume,
            shard,
            threads,
            allow_failures,
            progress,
            log_interval,
            time_limit,
        }),
        Command::Merge {
            shards,
            output,
            allow_failures,
        } => merge(&shards, &output, allow_failures),
        Command::Surface {
            case,
            output,
            sample,
            seed,
            points,
            body,
            exact,
        } => surface(
            &case,
            &output,
            &SurfaceArgs {
                sample,
                seed,
                points,
                body,
                exact,
            },
        ),
        Command::Check { file, threads } => check(&file, threads),
        Command::Law {
            table,
            output,
            args,
        } => law(&table, &output, &args),
        Command::Bench {
            sizes,
            pressures,
            only,
            finest,
            target,
            cube,
            degree,
            levels,
            max_levels,
            max_dofs,
            edge_neighbours,
            fixed,
            refinement,
        } => {
            let run = || -> tcgen::Result<()> {
                if only == Some(BenchPart::EggBox) {
                    let adaptive = tcgen::bench::EggBoxAdaptive {
                        target,
                        max_levels,
                        max_dofs,
                        edge_neighbours,
                    };
                    let mesh = tcgen::bench::EggBoxMesh::from_options(fixed, levels, adaptive)?;
                    let mut case = tcgen::bench::egg_box_case(mesh)?;
                    case.discretization.refinement = match refinement {
                        RefinementArg::Dyadic => tcgen::sample::case::RefinementPattern::Dyadic,
                        RefinementArg::Alternating => {
                            tcgen::sample::case::RefinementPattern::Alternating
                        }
                    };
                    let (phases, rows) = tcgen::bench::egg_box_bench(&case)?;
                    print!(
                        "{}",
                        tcgen::bench::format_egg_box_bench(&case, phases, &rows)
                    );
                    return Ok(());
                }
                if only == Some(BenchPart::Solvers3d) {
                    let rows = tcgen::bench::solver_3d_bench(degree, &cube)?;
                    print!("{}", tcgen::bench::format_solver_3d_bench(degree, &rows));
                    return Ok(());
                }
                if only.is_none() || only == Some(BenchPart::Solvers) {
                    tcgen::bench::main_bench(&sizes)?;
                }
                if only.is_none() || only == Some(BenchPart::Micro) {
                    let b = tcgen::bench::micro_sample_bench(pressures)?;
                    print!("{}", tcgen::bench::format_micro_bench(&b));
                }
                if only.is_none() || only == Some(BenchPart::Accuracy) {
                    let rows = tcgen::bench::adaptivity_bench(finest)?;
                    print!("{}", tcgen::bench::format_accuracy_bench(&rows));
                }
                if only.is_none() || only == Some(BenchPart::Effectivity) {
                    let rows = tcgen::bench::effectivity_bench(target, pressures)?;
                    print!("{}", tcgen::bench::format_effectivity_bench(target, &rows));
                }
                Ok(())
            };
            match run() {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
            }
        }
    }
}
