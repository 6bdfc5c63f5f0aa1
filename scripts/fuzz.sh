#!/usr/bin/env bash
# Runs every fuzz target in fuzz/ for SECONDS seconds (default 10), starting from
# the committed seed corpus (fuzz/corpus/<target>/, which is read, never written:
# new inputs go to a scratch folder). Installs a nightly toolchain when it is
# missing. A crash stops the run with the fuzzer's report; the input is saved
# under fuzz/artifacts/<target>/.
#
#     bash scripts/fuzz.sh [SECONDS] [TARGET...]
#
# FUZZ_SEED=N fixes libFuzzer's random seed: the inputs tried are then the same
# sequence on every machine (a faster machine gets further along it), so a run
# that passed locally for longer covers what the test command tries. Without
# it each run explores new inputs.
#
# The targets are built with cargo itself and the instrumentation flags that
# `cargo fuzz build --sanitizer none` passes (libFuzzer's coverage counters,
# comparison tracing, `--cfg fuzzing`, debug assertions and overflow checks),
# so the test command needs no cargo-fuzz; the binaries land where cargo fuzz
# puts them (fuzz/target/<host>/release/), and `cargo +nightly fuzz run -s
# none TARGET` works on the same workspace for longer sessions.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-10}"
shift || true

if ! rustup run nightly rustc --version >/dev/null 2>&1; then
  rustup toolchain install nightly --profile minimal
fi

# The fuzz workspace keeps its own target folder (fuzz/target).
unset CARGO_TARGET_DIR
host="$(rustup run nightly rustc -vV | sed -n 's/^host: //p')"

if [ "$#" -gt 0 ]; then
  targets=("$@")
else
  mapfile -t targets < <(sed -n '/^\[\[bin\]\]/,/^path/s/^name = "\(.*\)"/\1/p' fuzz/Cargo.toml)
fi

# Address Sanitizer adds little to safe Rust and halves the speed, so none.
flags="-Cpasses=sancov-module"
flags+=" -Cllvm-args=-sanitizer-coverage-level=4"
flags+=" -Cllvm-args=-sanitizer-coverage-inline-8bit-counters"
flags+=" -Cllvm-args=-sanitizer-coverage-pc-table"
flags+=" -Cllvm-args=-sanitizer-coverage-trace-compares"
flags+=" -Cllvm-args=-simplifycfg-branch-fold-threshold=0"
flags+=" --cfg fuzzing -Cdebug-assertions -Coverflow-checks -Ccodegen-units=16"
case "$host" in *-linux-*) flags+=" -Cllvm-args=-sanitizer-coverage-stack-depth" ;; esac
RUSTFLAGS="$flags" cargo +nightly build --manifest-path fuzz/Cargo.toml \
  --target "$host" --release --config 'profile.release.debug="line-tables-only"' \
  --bins --quiet

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
for target in "${targets[@]}"; do
  mkdir -p "$scratch/$target" "fuzz/artifacts/$target"
  log="$scratch/$target.log"
  if ! "fuzz/target/$host/release/$target" -artifact_prefix="fuzz/artifacts/$target/" \
    "$scratch/$target" "fuzz/corpus/$target" \
    -max_total_time="$seconds" -print_final_stats=1 ${FUZZ_SEED:+-seed="$FUZZ_SEED"} >"$log" 2>&1; then
    tail -n 80 "$log"
    echo "fuzz target $target failed; the input is in fuzz/artifacts/$target/" >&2
    exit 1
  fi
  runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")"
  echo "$target: ${runs:-?} inputs in ${seconds} s, no failure"
done
