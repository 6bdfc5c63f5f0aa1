#!/usr/bin/env bash
# Checks that the chip named in the board runner (`probe-rs run --chip NAME` in
# .cargo/config.toml and firmware/blackpill/.cargo/config.toml) is one that
# `probe-rs chip list` knows, and that probe-rs gives it the flash and RAM the
# top-level memory.x describes. Installs probe-rs (probe-rs-tools) when missing.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v probe-rs >/dev/null 2>&1; then
  cargo install probe-rs-tools --locked
fi
probe-rs --version

chip_of() { sed -n 's/^runner *= *"probe-rs run --chip \([A-Za-z0-9_-]*\)".*/\1/p' "$1"; }
chip="$(chip_of firmware/blackpill/.cargo/config.toml)"
root_chip="$(chip_of .cargo/config.toml)"
if [ -z "$chip" ] || [ "$chip" != "$root_chip" ]; then
  echo "board runners disagree or name no chip: '$chip' (firmware/blackpill) vs '$root_chip' (top level)" >&2
  exit 1
fi
# Captured first: grep -q stops reading early, which would fail probe-rs's write.
chips="$(probe-rs chip list)"
if ! grep -qx "[[:space:]]*$chip" <<<"$chips"; then
  echo "probe-rs chip list does not know $chip" >&2
  exit 1
fi
grep -q "FLASH : ORIGIN = 0x08000000, LENGTH = 512K" memory.x && grep -q "RAM   : ORIGIN = 0x20000000, LENGTH = 128K" memory.x \
  || { echo "memory.x no longer describes 512 KiB flash and 128 KiB RAM; update this check with it" >&2; exit 1; }
info="$(probe-rs chip info "$chip")"
# memory.x: FLASH 512K at 0x08000000, RAM 128K at 0x20000000.
grep -q "NVM: 0x08000000..0x08080000" <<<"$info" || { echo "$chip: flash differs from memory.x" >&2; echo "$info" >&2; exit 1; }
grep -q "RAM: 0x20000000..0x20020000" <<<"$info" || { echo "$chip: RAM differs from memory.x" >&2; echo "$info" >&2; exit 1; }
echo "$chip: known to probe-rs, 512 KiB flash at 0x08000000 and 128 KiB RAM at 0x20000000 as in memory.x"
