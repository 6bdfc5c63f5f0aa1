//! `cargo xtask test`: every test, on a fresh machine.
//!
//! Installs what is missing (the toolchain of `rust-toolchain.toml` with its
//! targets, QEMU, flip-link (the firmwares' linker), the toolchain of the
//! workspace's minimum Rust version), then checks
//! formatting and lints, the documentation, packaging and the minimum Rust
//! version, builds the library for bare-metal targets, and runs the whole
//! suite: host unit and system tests, the QEMU firmware parity and
//! instruction-count tests (Cortex-M4) and the SPI display screendump test
//! (Cortex-M3), the board firmware's link check and the host test of its
//! display path, the board's chip name and memory against probe-rs's target
//! description, every fuzz target for a short time (built and run beside the
//! tests, which leave a core idle much of the time), and the main job (a
//! built-in scene rendered to an image). Each step's heading shows the minutes
//! and seconds since the start.

use crate::firmware::DebugInfo;
use crate::run::{cargo, installed, output, repo_root, status};
use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;

/// The flip-link version the firmwares link with.
const FLIP_LINK_VERSION: &str = "0.1.12";

/// Prints step headings with the time since the start.
struct Steps(Instant);

impl Steps {
    fn step(&self, what: &str) {
        let s = self.0.elapsed().as_secs();
        println!("== [{}:{:02}] {what}", s / 60, s % 60);
    }
}

/// `cargo` with `args` (split at spaces) in the repository root.
fn cargo_args(args: &str) -> Command {
    let mut command = cargo();
    command.args(args.split_whitespace());
    command
}

/// Installs the targets, QEMU and flip-link when missing.
fn setup() -> Result<(), String> {
    // The toolchain rust-toolchain.toml names, with its components and targets
    // (older rustup installs it on first use instead); best effort.
    let _ = Command::new("rustup")
        .args(["toolchain", "install"])
        .output();
    let _ = Command::new("rustup")
        .args(["component", "add", "rustfmt", "clippy"])
        .output();
    status(
        Command::new("rustup")
            .args(["target", "add"])
            .args(toolchain_targets()?),
    )?;
    if !installed("qemu-system-arm") {
        let uid = output(Command::new("id").arg("-u")).unwrap_or_default();
        if uid.trim() != "0" {
            return Err("qemu-system-arm is missing and installing it needs root: apt-get install -y qemu-system-arm".into());
        }
        status(Command::new("apt-get").arg("update"))?;
        status(
            Command::new("apt-get")
                .env("DEBIAN_FRONTEND", "noninteractive")
                .args(["install", "-y", "qemu-system-arm"]),
        )?;
    }
    let version = output(Command::new("qemu-system-arm").arg("--version"))?;
    println!("{}", version.lines().next().unwrap_or(""));
    // The firmwares link through flip-link (the stack below the statics).
    if !installed("flip-link") {
        status(cargo().args([
            "install",
            "flip-link",
            "--locked",
            "--version",
            FLIP_LINK_VERSION,
        ]))?;
    }
    Ok(())
}

/// The bare-metal targets `rust-toolchain.toml` names (its `targets = [...]`
/// line), which the firmwares and the library are built for.
fn toolchain_targets() -> Result<Vec<String>, String> {
    let path = repo_root().join("rust-toolchain.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let list = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("targets = "))
        .ok_or_else(|| format!("{}: no `targets = [...]` line", path.display()))?;
    let targets: Vec<String> = list
        .trim_matches(['[', ']'])
        .split(',')
        .map(|t| t.trim().trim_matches('"').to_string())
        .filter(|t| !t.is_empty())
        .collect();
    if targets.is_empty() {
        return Err(format!("{}: the targets list is empty", path.display()));
    }
    Ok(targets)
}

/// Sets up a `cargo build` to lint the workspace's own crates with clippy,
/// warnings denied, while it builds them: clippy's driver takes rustc's place
/// for them (cargo's `RUSTC_WORKSPACE_WRAPPER`) and reads its arguments from
/// `CLIPPY_ARGS`, separated as `cargo clippy -- -D warnings` passes them.
/// `driver` is [`clippy_driver`]'s path.
fn linted<'a>(build: &'a mut Command, driver: &str) -> &'a mut Command {
    build.env("RUSTC_WORKSPACE_WRAPPER", driver).env(
        "CLIPPY_ARGS",
        "-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__",
    )
}

/// The path of the pinned toolchain's clippy driver.
fn clippy_driver() -> Result<String, String> {
    let path = output(
        Command::new("rustup")
            .args(["which", "clippy-driver"])
            .current_dir(repo_root()),
    )?;
    Ok(path.trim().to_string())
}

/// The workspace's `rust-version`.
fn minimum_rust_version() -> Result<String, String> {
    let path = repo_root().join("Cargo.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    text.lines()
        .find_map(|l| l.strip_prefix("rust-version = "))
        .map(|v| v.trim().trim_matches('"').to_string())
        .ok_or_else(|| format!("{}: no rust-version", path.display()))
}

/// The workspace members that declare its `rust-version`
/// (`rust-version.workspace = true`), by package name.
fn crates_declaring_rust_version() -> Result<Vec<String>, String> {
    let read = |path: PathBuf| {
        std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))
    };
    let root = repo_root();
    let workspace = read(root.join("Cargo.toml"))?;
    let members = workspace
        .lines()
        .find_map(|l| l.strip_prefix("members = "))
        .ok_or("Cargo.toml: no `members = [...]` line")?;
    let mut names = Vec::new();
    for member in members.trim_matches(['[', ']']).split(',') {
        let member = member.trim().trim_matches('"');
        if member.is_empty() {
            continue;
        }
        let manifest = read(root.join(member).join("Cargo.toml"))?;
        if manifest
            .lines()
            .any(|l| l.trim() == "rust-version.workspace = true")
        {
            let name = manifest
                .lines()
                .find_map(|l| l.strip_prefix("name = "))
                .ok_or_else(|| format!("{member}/Cargo.toml: no package name"))?;
            names.push(name.trim().trim_matches('"').to_string());
        }
    }
    if names.is_empty() {
        return Err("no workspace member declares the workspace's rust-version".into());
    }
    Ok(names)
}

/// Runs `cargo xtask test`.
pub fn run() -> Result<(), String> {
    let steps = Steps(Instant::now());
    steps.step("setup");
    setup()?;

    steps.step("format");
    status(&mut cargo_args("fmt --all -- --check"))?;
    status(&mut cargo_args(
        "fmt --manifest-path firmware/qemu/Cargo.toml -- --check",
    ))?;
    status(&mut cargo_args(
        "fmt --manifest-path firmware/blackpill/Cargo.toml -- --check",
    ))?;
    status(&mut cargo_args(
        "fmt --manifest-path fuzz/Cargo.toml -- --check",
    ))?;

    steps.step("clippy");
    status(&mut cargo_args(
        "clippy --workspace --all-targets -- -D warnings",
    ))?;
    // The firmware workspaces are linted while they build: cargo runs clippy's
    // driver in place of rustc for their own crates (as `cargo clippy` does,
    // which only checks) and rustc for the dependencies. Those are then
    // compiled once, for the lints and for the tests' firmware builds, instead
    // of checked for one and built for the other; the lints' builds leave out
    // the debug information as the tests' do (`firmware::DebugInfo`), or the
    // tests would compile everything again. The board's minimal example
    // (README, "Add it to your firmware") is among them.
    let driver = clippy_driver()?;
    for args in [
        "--manifest-path firmware/qemu/Cargo.toml --release --target thumbv7em-none-eabihf",
        "--manifest-path firmware/qemu/Cargo.toml --release --no-default-features --features oled --target thumbv7m-none-eabi",
        "--manifest-path firmware/blackpill/Cargo.toml --release --target thumbv7em-none-eabihf --bins --examples",
    ] {
        let mut build = cargo_args(&format!("build {args}"));
        status(linted(DebugInfo::Dropped.apply_to(&mut build), &driver))?;
    }

    steps.step("the library's documentation, its private items too, builds without warnings (broken links included)");
    status(cargo_args("doc -p mcu-abuffer --no-deps").env("RUSTDOCFLAGS", "-D warnings"))?;
    // The private items' documentation too: its links are the maintainers'
    // map of the pipeline. (A separate run: with private items documented,
    // rustdoc no longer warns about public documentation linking to them.)
    status(
        cargo_args("doc -p mcu-abuffer --no-deps --document-private-items")
            .env("RUSTDOCFLAGS", "-D warnings"),
    )?;

    steps.step("the library and the scene crate package for crates.io (dry run)");
    status(&mut cargo_args(
        "publish --dry-run --allow-dirty -p mcu-abuffer -p abuffer-scenes",
    ))?;

    steps.step("the declared minimum Rust version (workspace rust-version) builds the crates that declare it");
    let msrv = minimum_rust_version()?;
    output(Command::new("rustup").args(["toolchain", "install", &msrv, "--profile", "minimal"]))?;
    // The crates a firmware or a user's program depends on, with their tests
    // and examples (and the display emulator, which the tests use); the tools
    // declare no minimum (the workspace's Cargo.toml says why).
    let mut check = cargo();
    check
        .env("CARGO_TARGET_DIR", "target/msrv")
        .arg(format!("+{msrv}"))
        .args([
            "check",
            "--all-targets",
            "--features",
            "abuffer-panel/emulator",
        ]);
    for name in crates_declaring_rust_version()? {
        check.args(["-p", &name]);
    }
    status(&mut check)?;

    steps.step("library for Cortex-M4F and Cortex-M0+");
    // One cargo for both targets: it builds them side by side (the release
    // profile's single codegen unit keeps each on one core). Nothing reads
    // their debug information.
    status(DebugInfo::Dropped.apply_to(&mut cargo_args(
        "build -p mcu-abuffer --release --target thumbv7em-none-eabihf --target thumbv6m-none-eabi",
    )))?;

    // The fuzz targets build (about two minutes of their own, with
    // instrumentation) and run beside the tests: the QEMU tests leave a core
    // idle while a firmware links or QEMU runs. Their report follows the tests'.
    // A fixed seed: the same inputs on every machine, in the same order.
    // Exploring new inputs is `cargo xtask fuzz --seconds N`.
    let fuzz = std::thread::spawn(|| {
        crate::fuzz::report(&crate::fuzz::FuzzArgs {
            seconds: 10,
            seed: Some(1),
            targets: Vec::new(),
        })
    });

    steps.step("tests (host, QEMU Cortex-M4 parity and counts, QEMU Cortex-M3 OLED screendump, board link and display path), the fuzz targets building alongside");
    // The firmware tests skip themselves when QEMU or a Cortex-M target is
    // missing; both were installed above, so a missing one must fail instead.
    let tests = status(cargo_args("test --workspace").env("ABUFFER_REQUIRE_QEMU", "1"));
    // Waited for even when the tests failed, so that no fuzzer outlives this command.
    let fuzz = fuzz
        .join()
        .unwrap_or_else(|_| Err("the fuzz run panicked".into()));
    tests?;

    steps.step("board: the runner's chip is one probe-rs knows, with memory.x's flash and RAM (probe-rs if installed, else the copy of its target description)");
    for line in crate::board_chip::check()? {
        println!("{line}");
    }

    steps.step(
        "fuzz (run beside the tests): 10 s per target from the seed corpus with a fixed seed",
    );
    for line in fuzz? {
        println!("{line}");
    }

    steps.step("main job: render a built-in scene");
    // The README's first command, built with the test profile that the tests
    // above compiled it with (the release build would add minutes here).
    status(&mut cargo_args(
        "run --profile test -p host-sim -- render --scene teapot --out target/teapot.png",
    ))?;
    steps.step("done");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_minimum_rust_check_takes_the_library_crates_and_not_the_tools() {
        let names = crates_declaring_rust_version().unwrap();
        assert!(names.iter().any(|n| n == "mcu-abuffer"), "{names:?}");
        assert!(
            names.iter().all(|n| n != "host-sim" && n != "xtask"),
            "{names:?}"
        );
        assert!(minimum_rust_version().unwrap().starts_with("1."));
    }
}
