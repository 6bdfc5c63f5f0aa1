//! The system tests that run on the host, one module per file beside this one,
//! built as one binary (see `tests/Cargo.toml`). One file's tests run with, for
//! example, `cargo test -p system-tests --test host oracle::`.

#[path = "board_display.rs"]
mod board_display;
#[path = "coverage_bound.rs"]
mod coverage_bound;
#[path = "extreme.rs"]
mod extreme;
#[path = "fuzz_regressions.rs"]
mod fuzz_regressions;
#[path = "memory.rs"]
mod memory;
#[path = "merge_insert.rs"]
mod merge_insert;
#[path = "oracle.rs"]
mod oracle;
#[path = "ranges.rs"]
mod ranges;
#[path = "top_left.rs"]
mod top_left;

/// With `autotests = false`, Cargo no longer finds test files by itself: a new
/// file in this folder must be a module above, a module of `firmware.rs` or a
/// `[[test]]` of `tests/Cargo.toml`, or its tests would never run.
#[test]
fn every_test_file_is_built() {
    let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    // The test binaries whose modules are the other files: name and source.
    let binaries = [
        ("host.rs", include_str!("host.rs")),
        ("firmware.rs", include_str!("firmware.rs")),
    ];
    let manifest = std::fs::read_to_string(crate_dir.join("Cargo.toml")).unwrap();
    let folder = crate_dir.join("tests");
    let mut unbuilt = Vec::new();
    for entry in std::fs::read_dir(&folder).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if !name.ends_with(".rs") || binaries.iter().any(|(binary, _)| *binary == name) {
            continue;
        }
        let as_module = format!("#[path = \"{name}\"]");
        let as_binary = format!("path = \"tests/{name}\"");
        let is_module = binaries
            .iter()
            .any(|(_, source)| source.contains(&as_module));
        if !is_module && !manifest.contains(&as_binary) {
            unbuilt.push(name);
        }
    }
    assert!(
        unbuilt.is_empty(),
        "{unbuilt:?} in {} are not built: add each as a module of host.rs or firmware.rs, or a [[test]] of tests/Cargo.toml",
        folder.display()
    );
}
