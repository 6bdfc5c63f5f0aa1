//! `cargo xtask`: the project's tooling (see the crate documentation of
//! `xtask` and `cargo xtask --help`).

use clap::{Parser, Subcommand};
use std::process::ExitCode;
use xtask::{bench, board_chip, fuzz, results, sizing, test_command};

#[derive(Parser)]
#[command(
    name = "cargo xtask",
    about = "The project's tooling: tests, firmware builds and runs under QEMU, benchmarks, profiles, fuzzing, reference images and results"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Every test on a fresh machine, with all set-up (what CI runs).
    Test,
    /// Runs the fuzz targets from the seed corpus.
    Fuzz(fuzz::FuzzArgs),
    /// Instructions per frame on the Cortex-M4 under QEMU, per scene and method.
    QemuBench(bench::BenchArgs),
    /// Instructions per function and source file of one teapot frame on the
    /// Cortex-M4 (docs/m4-profile/), from QEMU's trace.
    Profile,
    /// `host-sim fit`, then the QEMU M4 firmware built with these parameters
    /// and the linker's answer read from its ELF.
    FitLink(host_sim::fit::FitArgs),
    /// `host-sim tune`, then the winner's instructions per frame under QEMU.
    Tune(host_sim::tune::TuneArgs),
    /// The board's chip against probe-rs's target description.
    BoardChip,
    /// Regenerates the reference renderings in docs/images/.
    ReferenceImages,
    /// Regenerates the shading comparisons in docs/images/shading-*.
    ShadingImages,
    /// Regenerates the z-buffer tables and images of docs/results.md.
    ZbufferTable {
        /// Timings per configuration (the fastest counts).
        #[arg(long, default_value_t = 9)]
        repeat: u32,
    },
    /// Regenerates everything else in docs/results/ that docs/results.md reports.
    Results,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Test => test_command::run(),
        Command::Fuzz(args) => fuzz::run(args),
        Command::QemuBench(args) => bench::run_bench(args),
        Command::Profile => bench::profile(),
        Command::FitLink(args) => sizing::fit_link(args),
        Command::Tune(args) => sizing::tune(args),
        Command::BoardChip => board_chip::check().map(|lines| {
            for line in lines {
                println!("{line}");
            }
        }),
        Command::ReferenceImages => results::reference_images(),
        Command::ShadingImages => results::shading_images(),
        Command::ZbufferTable { repeat } => results::zbuffer_table(*repeat),
        Command::Results => results::results(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
