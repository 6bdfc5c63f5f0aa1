#!/usr/bin/env bash
# Runs every fuzz target in fuzz/ for SECONDS seconds (default 10), starting from
# the committed seed corpus (fuzz/corpus/<target>/, which is read, never written:
# new inputs go to a scratch folder). Installs a nightly toolchain and cargo-fuzz
# when they are missing. A crash stops the run with the fuzzer's report; the input
# is saved under fuzz/artifacts/<target>/.
#
#     bash scripts/fuzz.sh [SECONDS] [TARGET...]
#
# FUZZ_SEED=N fixes libFuzzer's random seed: the inputs tried are then the same
# sequence on every machine (a faster machine gets further along it), so a run
# that passed locally for longer covers what the test command tries. Without
# it each run explores new inputs.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-10}"
shift || true

if ! rustup run nightly rustc --version >/dev/null 2>&1; then
  rustup toolchain install nightly --profile minimal
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
  cargo install cargo-fuzz --locked
fi

# The fuzz workspace keeps its own target folder (fuzz/target).
unset CARGO_TARGET_DIR
# Address Sanitizer adds little to safe Rust and halves the speed; overflow
# checks and debug assertions stay on (cargo fuzz's default).
flags=(--sanitizer none --codegen-units 16)

if [ "$#" -gt 0 ]; then
  targets=("$@")
else
  mapfile -t targets < <(cargo +nightly fuzz list)
fi
cargo +nightly fuzz build "${flags[@]}" >/dev/null

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
for target in "${targets[@]}"; do
  mkdir -p "$scratch/$target"
  log="$scratch/$target.log"
  if ! cargo +nightly fuzz run "${flags[@]}" "$target" "$scratch/$target" "fuzz/corpus/$target" -- \
    -max_total_time="$seconds" -print_final_stats=1 ${FUZZ_SEED:+-seed="$FUZZ_SEED"} >"$log" 2>&1; then
    tail -n 80 "$log"
    echo "fuzz target $target failed; the input is in fuzz/artifacts/$target/" >&2
    exit 1
  fi
  runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")"
  echo "$target: ${runs:-?} inputs in ${seconds} s, no failure"
done
