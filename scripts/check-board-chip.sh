#!/usr/bin/env bash
# Checks the board's chip against probe-rs's target description: the chip named in
# the board runners (`probe-rs run --chip NAME` in .cargo/config.toml and
# firmware/blackpill/.cargo/config.toml) must be one probe-rs knows, with the flash
# and RAM that the top-level memory.x describes.
#
# When probe-rs is installed, the check asks `probe-rs chip list` and
# `probe-rs chip info`, and also requires the copy of probe-rs's description of the
# chip in firmware/blackpill/probe-rs-target/ to say what probe-rs says, so the copy
# cannot go stale unnoticed. When it is not, the check reads that copy instead (it
# does not install probe-rs).
set -euo pipefail
cd "$(dirname "$0")/.."

fail() { echo "check-board-chip: $*" >&2; exit 1; }

chip_of() { sed -n 's/^runner *= *"probe-rs run --chip \([A-Za-z0-9_-]*\)".*/\1/p' "$1"; }
chip="$(chip_of firmware/blackpill/.cargo/config.toml)"
root_chip="$(chip_of .cargo/config.toml)"
if [ -z "$chip" ] || [ "$chip" != "$root_chip" ]; then
  fail "board runners disagree or name no chip: '$chip' (firmware/blackpill/.cargo/config.toml) vs '$root_chip' (.cargo/config.toml)"
fi

grep -q "FLASH : ORIGIN = 0x08000000, LENGTH = 512K" memory.x && grep -q "RAM   : ORIGIN = 0x20000000, LENGTH = 128K" memory.x \
  || fail "memory.x no longer describes 512 KiB flash at 0x08000000 and 128 KiB RAM at 0x20000000; update this check with it"
# memory.x's regions as `probe-rs chip info` prints them.
flash="NVM: 0x08000000..0x08080000"
ram="RAM: 0x20000000..0x20020000"

copy_dir=firmware/blackpill/probe-rs-target
copy_file="$copy_dir/$chip.yaml"
[ -f "$copy_file" ] || fail "$copy_file is missing: no copy of probe-rs's target description for $chip, the chip the runners name (is the name right? the copy is the chip's entry in probe-rs/targets/ of the probe-rs sources)"

# The copy reduced to what `probe-rs chip info` prints: its name, then one line per
# core and per memory region. Only the subset of YAML that probe-rs's target files
# use is read.
copy="$(python3 - "$copy_file" <<'PY'
import re, sys

path = sys.argv[1]
def bad(message):
    sys.exit(f"check-board-chip: {path}: {message}")

family, variants, section = None, [], None
for number, raw in enumerate(open(path, encoding="utf-8"), 1):
    line = re.sub(r"(^|\s)#.*", "", raw).rstrip()
    if not line:
        continue
    indent, text = len(line) - len(line.lstrip()), line.strip()
    if indent == 0:
        section = None
        if text.startswith("name:"):
            family = text[5:].strip()
        elif text.startswith("- name:"):
            variants.append({"name": text[7:].strip(), "cores": [], "regions": []})
        elif text != "variants:":
            bad(f"line {number}: unexpected top-level line {text!r}")
        continue
    if not variants:
        bad(f"line {number}: {text!r} is outside a variant")
    variant = variants[-1]
    if indent == 2 and not text.startswith("- "):
        section = text.split(":")[0]
    elif section == "cores":
        if text.startswith("- name:"):
            variant["cores"].append([text[7:].strip(), None])
        elif text.startswith("type:") and variant["cores"]:
            variant["cores"][-1][1] = text[5:].strip()
    elif section == "memory_map":
        kind = re.fullmatch(r"- !(Nvm|Ram|Generic)", text)
        bound = re.fullmatch(r"(start|end): *(0x[0-9a-fA-F]+|[0-9]+)", text)
        if kind:
            variant["regions"].append({"kind": {"Nvm": "NVM", "Ram": "RAM"}.get(kind[1], kind[1])})
        elif bound and variant["regions"]:
            variant["regions"][-1][bound[1]] = int(bound[2], 0)

if not family:
    bad("no family name (top-level `name:`)")
if len(variants) != 1:
    bad(f"expected one variant, found {len(variants)}")
variant = variants[0]
if not variant["cores"] or any(kind is None for _, kind in variant["cores"]):
    bad(f"{variant['name']}: no cores, or a core without a type")
if not variant["regions"]:
    bad(f"{variant['name']}: no memory regions")
print(f"chip: {variant['name']}")
for name, kind in variant["cores"]:
    print(f"core: {name.lower()} ({kind.lower()})")
for region in variant["regions"]:
    if "start" not in region or "end" not in region or region["start"] >= region["end"]:
        bad(f"{variant['name']}: a {region['kind']} region without a valid start..end range")
    print(f"{region['kind']}: {region['start']:#010x}..{region['end']:#010x}")
PY
)"
copy_chip="$(sed -n 's/^chip: //p' <<<"$copy")"
copy="$(grep -v '^chip: ' <<<"$copy")"
[ "$copy_chip" = "$chip" ] || fail "$copy_file describes $copy_chip, not $chip (the chip the runners name)"

if command -v probe-rs >/dev/null 2>&1; then
  version="$(probe-rs --version | head -n 1)"
  # Captured first: grep -q stops reading early, which would fail probe-rs's write.
  chips="$(probe-rs chip list)"
  grep -qx "[[:space:]]*$chip" <<<"$chips" || fail "probe-rs chip list ($version) does not know $chip"
  info="$(probe-rs chip info "$chip")"
  reported="$(sed -n -e 's/^ *- \(.*\) (\(.*\))$/core: \L\1 (\2)/p' \
    -e 's/^\(NVM\|RAM\|Generic\): \(0x[0-9a-fA-F]*\.\.0x[0-9a-fA-F]*\).*/\1: \2/p' <<<"$info")"
  if [ "$(sort <<<"$reported")" != "$(sort <<<"$copy")" ]; then
    echo "probe-rs chip info $chip ($version):" >&2
    echo "$info" >&2
    fail "$copy_file no longer matches probe-rs's description of $chip (differences, < probe-rs, > the copy):
$(diff <(sort <<<"$reported") <(sort <<<"$copy") || true)
refresh the copy from probe-rs/targets/ of the installed probe-rs version"
  fi
  source_line="checked against probe-rs itself ($version: chip list and chip info), and $copy_file agrees with it"
  where="probe-rs chip info $chip"
else
  reported="$copy"
  source_line="checked against the copy of probe-rs's target description in $copy_dir (probe-rs not installed)"
  where="$copy_file"
fi

regions() { awk '/^(NVM|RAM|Generic):/ { printf "%s%s", sep, $0; sep = "; " }' <<<"$reported"; }
grep -qxF "$flash" <<<"$reported" || fail "$where: $chip has no ${flash%%:*} region ${flash#*: } (memory.x: 512K flash at 0x08000000); its regions: $(regions)"
grep -qxF "$ram" <<<"$reported" || fail "$where: $chip has no ${ram%%:*} region ${ram#*: } (memory.x: 128K RAM at 0x20000000); its regions: $(regions)"
echo "$source_line"
echo "$chip: described by probe-rs, with 512 KiB flash at 0x08000000 and 128 KiB RAM at 0x20000000 as in memory.x"
