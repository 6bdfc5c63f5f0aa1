//! `cargo xtask fuzz`: runs every fuzz target in `fuzz/` for a number of
//! seconds, starting from the committed seed corpus (`fuzz/corpus/<target>/`,
//! which is read, never written: new inputs go to a scratch folder). A crash
//! stops the run with the fuzzer's report; the input is saved under
//! `fuzz/artifacts/<target>/`.
//!
//! A fixed `--seed` makes libFuzzer try the same sequence of inputs on every
//! machine (a faster machine gets further along it), so a run that passed
//! locally for longer covers what the test command tries. Without it each run
//! explores new inputs.
//!
//! The targets are built with cargo itself and the instrumentation flags that
//! `cargo fuzz build --sanitizer none` passes (libFuzzer's coverage counters,
//! comparison tracing, `--cfg fuzzing`, debug assertions and overflow checks).
//! Those are stable compiler options, so the project's own toolchain
//! (`rust-toolchain.toml`) builds the targets and nothing more is installed;
//! the binaries land where cargo fuzz puts them
//! (`fuzz/target/<host>/release/`), and `cargo +nightly fuzz run -s none
//! TARGET` works on the same workspace for longer sessions.

use crate::run::{captured, cargo, describe, output, program, repo_root, scratch_dir};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Arguments of `cargo xtask fuzz`.
#[derive(clap::Args, Debug)]
pub struct FuzzArgs {
    /// Seconds per target.
    #[arg(long, default_value_t = 10)]
    pub seconds: u32,
    /// libFuzzer's random seed (the same inputs on every machine).
    #[arg(long)]
    pub seed: Option<u32>,
    /// Targets to run (default: every `[[bin]]` of `fuzz/Cargo.toml`).
    pub targets: Vec<String>,
}

/// The instrumentation of `cargo fuzz build --sanitizer none` (Address
/// Sanitizer adds little to safe Rust and halves the speed, so none).
fn rustflags(host: &str) -> String {
    let mut flags = vec![
        "-Cpasses=sancov-module",
        "-Cllvm-args=-sanitizer-coverage-level=4",
        "-Cllvm-args=-sanitizer-coverage-inline-8bit-counters",
        "-Cllvm-args=-sanitizer-coverage-pc-table",
        "-Cllvm-args=-sanitizer-coverage-trace-compares",
        "-Cllvm-args=-simplifycfg-branch-fold-threshold=0",
        "--cfg fuzzing",
        "-Cdebug-assertions",
        "-Coverflow-checks",
        "-Ccodegen-units=16",
    ];
    if host.contains("-linux-") {
        flags.push("-Cllvm-args=-sanitizer-coverage-stack-depth");
    }
    flags.join(" ")
}

/// The fuzz targets: the `name` of every `[[bin]]` in `fuzz/Cargo.toml`.
pub fn targets() -> Result<Vec<String>, String> {
    let path = repo_root().join("fuzz/Cargo.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut names = Vec::new();
    let mut in_bin = false;
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            in_bin = line == "[[bin]]";
        } else if in_bin {
            if let Some(value) = line.strip_prefix("name") {
                let name = value
                    .trim_start()
                    .trim_start_matches('=')
                    .trim()
                    .trim_matches('"');
                names.push(name.to_string());
            }
        }
    }
    if names.is_empty() {
        return Err(format!("{}: no [[bin]] targets", path.display()));
    }
    Ok(names)
}

/// Runs `cargo xtask fuzz`, printing what [`report`] returns.
pub fn run(args: &FuzzArgs) -> Result<(), String> {
    for line in report(args)? {
        println!("{line}");
    }
    Ok(())
}

/// Builds the fuzz targets and runs each for `args.seconds`, as many at a
/// time as the machine has cores (each libFuzzer process uses one). Prints
/// nothing, so that it can run beside other work: returns the lines to show
/// (the build's command and warnings, one line per target, in the order of
/// `fuzz/Cargo.toml`), or the first failure with the fuzzer's last lines.
pub fn report(args: &FuzzArgs) -> Result<Vec<String>, String> {
    // The toolchain of `rust-toolchain.toml` (run from the repository's root).
    let version = output(program("rustc").arg("-vV"))?;
    let host = version
        .lines()
        .find_map(|l| l.strip_prefix("host: "))
        .ok_or("rustc -vV printed no host")?
        .to_string();
    let targets = if args.targets.is_empty() {
        targets()?
    } else {
        args.targets.clone()
    };
    // The fuzz workspace keeps its own target folder (fuzz/target).
    let mut build = cargo();
    build
        .env_remove("CARGO_TARGET_DIR")
        .env("RUSTFLAGS", rustflags(&host))
        .args([
            "build",
            "--manifest-path",
            "fuzz/Cargo.toml",
            "--target",
            &host,
        ])
        .args([
            "--release",
            "--config",
            "profile.release.debug=\"line-tables-only\"",
        ])
        .args(["--bins", "--quiet"]);
    let mut lines = vec![format!("$ {}", describe(&build))];
    // Captured, not streamed: cargo's warnings join the returned lines.
    let built = captured(&mut build)?;
    lines.extend(
        String::from_utf8_lossy(&built.stderr)
            .lines()
            .map(String::from),
    );
    let scratch = scratch_dir("fuzz")?;
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let next = AtomicUsize::new(0);
    // Each worker takes the next target not yet taken.
    let mut outcomes: Vec<(usize, Result<String, String>)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers.min(targets.len()))
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let k = next.fetch_add(1, Ordering::Relaxed);
                        let Some(target) = targets.get(k) else {
                            return done;
                        };
                        let corpus = scratch.path().join(target);
                        done.push((k, run_target(&host, target, args, &corpus)));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| {
                h.join()
                    .unwrap_or_else(|_| vec![(usize::MAX, Err("a fuzz worker panicked".into()))])
            })
            .collect()
    });
    outcomes.sort_by_key(|(k, _)| *k);
    for (_, outcome) in outcomes {
        lines.push(outcome?);
    }
    Ok(lines)
}

/// Runs one fuzz target for `args.seconds` with the new inputs in `corpus`:
/// its line of the report, or its failure with the fuzzer's last 80 lines.
fn run_target(
    host: &str,
    target: &str,
    args: &FuzzArgs,
    corpus: &std::path::Path,
) -> Result<String, String> {
    let artifacts = format!("fuzz/artifacts/{target}/");
    crate::run::create_dir(corpus)?;
    crate::run::create_dir(&repo_root().join(&artifacts))?;
    let mut fuzzer = program(repo_root().join(format!("fuzz/target/{host}/release/{target}")));
    fuzzer
        .arg(format!("-artifact_prefix={artifacts}"))
        .arg(corpus)
        .arg(format!("fuzz/corpus/{target}"))
        .arg(format!("-max_total_time={}", args.seconds))
        .arg("-print_final_stats=1");
    if let Some(seed) = args.seed {
        fuzzer.arg(format!("-seed={seed}"));
    }
    let run = fuzzer
        .output()
        .map_err(|e| format!("`{}` did not start: {e}", describe(&fuzzer)))?;
    // libFuzzer reports on its standard error.
    let log = String::from_utf8_lossy(&run.stderr);
    if !run.status.success() {
        let lines: Vec<&str> = log.lines().collect();
        return Err(format!(
            "{}\nfuzz target {target} failed ({}); the input is in {artifacts}",
            lines[lines.len().saturating_sub(80)..].join("\n"),
            run.status
        ));
    }
    let runs = log
        .lines()
        .find_map(|l| l.strip_prefix("stat::number_of_executed_units:"))
        .map(str::trim)
        .unwrap_or("?");
    Ok(format!(
        "{target}: {runs} inputs in {} s, no failure",
        args.seconds
    ))
}
