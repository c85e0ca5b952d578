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
        /// Run only the cases whose name contains this text.
        #[arg(long)]
        filter: Option<String>,
        /// List the cases and exit.
        #[arg(long)]
        list: bool,
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
    },
    /// Print performance figures of assembly and the sparse solvers.
    Bench {
        /// Approximate numbers of unknowns to benchmark.
        #[arg(long, value_delimiter = ',', default_values_t = vec![20_000usize, 100_000])]
        sizes: Vec<usize>,
    },
}

fn verify(json: bool, filter: Option<String>, list: bool) -> ExitCode {
    let cases: Vec<_> = tcgen::verify::catalogue()
        .into_iter()
        .filter(|c| filter.as_deref().is_none_or(|f| c.name.contains(f)))
        .collect();
    if list {
        for c in &cases {
            println!("{:<28} {}", c.name, c.description);
        }
        return ExitCode::SUCCESS;
    }
    let mut all = Vec::new();
    let mut failed = 0;
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
                if json {
                    println!(
                        "{}",
                        serde_json::json!({"case": c.name, "error": e.to_string(), "pass": false})
                    );
                } else {
                    eprintln!("{:<28} ERROR: {e}", c.name);
                }
            }
        }
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

fn solve(path: &std::path::Path, json: bool, vtk: Option<std::path::PathBuf>) -> ExitCode {
    let case = match tcgen::sample::Case::read(path) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    if !json {
        println!(
            "{:>12} {:>9} {:>12} {:>12} {:>12} {:>12} {:>6} {:>6}  status",
            "pressure/Pa",
            "contact",
            "mean_gap/m",
            "approach/m",
            "jump/K",
            "k/(W/m2K)",
            "newton",
            "sc"
        );
    }
    let t = std::time::Instant::now();
    let result = tcgen::homogenize::solve_case(&case, vtk, |r| {
        if json {
            println!("{}", serde_json::to_string(r).expect("serializable"));
        } else {
            let status = match &r.status {
                tcgen::homogenize::Status::Converged => "converged".to_string(),
                tcgen::homogenize::Status::Failed(m) => format!("FAILED: {m}"),
            };
            println!(
                "{:>12.4e} {:>9.4} {:>12.4e} {:>12.4e} {:>12.6e} {:>12.4e} {:>6} {:>6}  {status}",
                r.pressure,
                r.interface.contact_fraction,
                r.interface.mean_gap,
                r.interface.approach,
                r.jump,
                r.conductance,
                r.newton_iterations,
                r.self_consistency_iterations
            );
        }
    });
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
        Command::Verify { json, filter, list } => verify(json, filter, list),
        Command::Solve { case, json, vtk } => solve(&case, json, vtk),
        Command::Bench { sizes } => match tcgen::bench::main_bench(&sizes) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
    }
}
