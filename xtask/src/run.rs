//! Running the programs the tasks are made of: each command is printed before
//! it runs, and a failure names the command and its exit status.

use std::path::{Path, PathBuf};
use std::process::Command;

pub use crate::firmware::repo_root;
pub use abuffer_test_support::ScratchDir;

/// `cargo` (the rustup proxy on `PATH`, so that `+toolchain` works) in the
/// repository root.
pub fn cargo() -> Command {
    let mut command = Command::new("cargo");
    command.current_dir(repo_root());
    command
}

/// A program in the repository root.
pub fn program(name: impl AsRef<std::ffi::OsStr>) -> Command {
    let mut command = Command::new(name);
    command.current_dir(repo_root());
    command
}

/// The command line of `command`, for messages, with the variables it sets in
/// front, as a shell takes them.
pub fn describe(command: &Command) -> String {
    let mut words = Vec::new();
    for (key, value) in command.get_envs() {
        if let Some(value) = value {
            let value = shell_word(&value.to_string_lossy());
            words.push(format!("{}={value}", key.to_string_lossy()));
        }
    }
    words.push(shell_word(&command.get_program().to_string_lossy()));
    words.extend(
        command
            .get_args()
            .map(|arg| shell_word(&arg.to_string_lossy())),
    );
    words.join(" ")
}

/// `word` quoted when a shell would otherwise split it or lose it.
fn shell_word(word: &str) -> String {
    if word.is_empty() || word.contains([' ', '"', '\'']) {
        format!("'{word}'")
    } else {
        word.to_string()
    }
}

/// Runs `command` with the terminal as its input and output; an error when it
/// cannot start or exits with a failure.
pub fn status(command: &mut Command) -> Result<(), String> {
    println!("$ {}", describe(command));
    let status = command
        .status()
        .map_err(|e| format!("`{}` did not start: {e}", describe(command)))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`{}` failed ({status})", describe(command)))
    }
}

/// Runs `command` quietly and returns its standard output; on failure the
/// error carries its standard error.
pub fn output(command: &mut Command) -> Result<String, String> {
    captured(command).map(|out| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// Runs `command` quietly and returns both its outputs; on failure the
/// error carries its standard error.
pub fn captured(command: &mut Command) -> Result<std::process::Output, String> {
    let out = command
        .output()
        .map_err(|e| format!("`{}` did not start: {e}", describe(command)))?;
    if out.status.success() {
        Ok(out)
    } else {
        Err(format!(
            "`{}` failed ({}):\n{}",
            describe(command),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Whether `program` runs (`program --version` succeeds).
pub fn installed(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The workspace's target folder (`CARGO_TARGET_DIR` or `target/`).
pub fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) => repo_root().join(dir),
        None => repo_root().join("target"),
    }
}

/// Builds `host-sim` with the release profile and returns its path.
pub fn host_sim_release() -> Result<PathBuf, String> {
    status(cargo().args(["build", "--release", "--quiet", "-p", "host-sim"]))?;
    Ok(target_dir().join("release").join("host-sim"))
}

/// Creates folder `dir` (and its parents).
pub fn create_dir(dir: &Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))
}

/// A scratch folder `xtask-PURPOSE-PID` under the system's temporary folder,
/// removed when dropped ([`abuffer_test_support::ScratchDir`]).
pub fn scratch_dir(purpose: &str) -> Result<ScratchDir, String> {
    ScratchDir::try_new(&format!("xtask-{purpose}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_described_command_shows_its_variables_and_quotes_spaced_words() {
        let mut command = Command::new("cargo");
        command
            .env("CARGO_PROFILE_RELEASE_DEBUG", "0")
            .env("RUSTFLAGS", "-C debuginfo=0")
            .env_remove("CARGO_TARGET_DIR")
            .args(["build", "--config", "a b", ""]);
        assert_eq!(
            describe(&command),
            "CARGO_PROFILE_RELEASE_DEBUG=0 RUSTFLAGS='-C debuginfo=0' cargo build --config 'a b' ''"
        );
    }
}
