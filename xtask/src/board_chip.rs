//! The board's chip against probe-rs's description of it (the port of
//! `scripts/check-board-chip.sh`): the chip named in the board runners
//! (`probe-rs run --chip NAME` in `.cargo/config.toml` and
//! `firmware/blackpill/.cargo/config.toml`) must be one probe-rs knows, with the
//! flash and RAM that the top-level `memory.x` describes.
//!
//! When probe-rs is installed, the check asks `probe-rs chip list` and
//! `probe-rs chip info`, and also requires the copy of probe-rs's description of
//! the chip in `firmware/blackpill/probe-rs-target/` to say what probe-rs says,
//! so the copy cannot go stale unnoticed. When it is not, the check reads that
//! copy instead (it does not install probe-rs).

use crate::run::{installed, output, program, repo_root};

/// The board firmware's Cargo configuration, with one runner.
const BOARD_CONFIG: &str = "firmware/blackpill/.cargo/config.toml";
/// The repository's Cargo configuration, with the other runner.
const ROOT_CONFIG: &str = ".cargo/config.toml";
/// The linker's memory layout, which must describe the chip's flash and RAM.
const MEMORY_X: &str = "memory.x";
/// The lines `memory.x` must contain.
const MEMORY_LINES: [&str; 2] = [
    "FLASH : ORIGIN = 0x08000000, LENGTH = 512K",
    "RAM   : ORIGIN = 0x20000000, LENGTH = 128K",
];
/// `memory.x`'s flash as `probe-rs chip info` prints it: kind and range.
const FLASH: (&str, &str) = ("NVM", "0x08000000..0x08080000");
/// `memory.x`'s RAM as `probe-rs chip info` prints it: kind and range.
const RAM: (&str, &str) = ("RAM", "0x20000000..0x20020000");
/// The folder of the copies of probe-rs's target descriptions.
const COPY_DIR: &str = "firmware/blackpill/probe-rs-target";

/// Checks the board's chip against probe-rs's description of it, and returns
/// the lines that say what it was checked against and what it found; an error
/// (starting `board chip check: `) says what does not agree.
pub fn check() -> Result<Vec<String>, String> {
    check_unprefixed().map_err(|message| format!("board chip check: {message}"))
}

/// [`check`], with errors not yet prefixed.
fn check_unprefixed() -> Result<Vec<String>, String> {
    let root = repo_root();
    let read_lossy = |path: &str| {
        std::fs::read(root.join(path))
            .map(|bytes| String::from_utf8_lossy(&bytes).into_owned())
            .map_err(|e| format!("{path}: {e}"))
    };

    let chip = runner_chip(&read_lossy(BOARD_CONFIG)?);
    let root_chip = runner_chip(&read_lossy(ROOT_CONFIG)?);
    if chip.is_empty() || chip != root_chip {
        return Err(format!(
            "board runners disagree or name no chip: '{chip}' ({BOARD_CONFIG}) vs '{root_chip}' ({ROOT_CONFIG})"
        ));
    }

    let memory = read_lossy(MEMORY_X);
    let memory_ok = memory
        .as_ref()
        .is_ok_and(|text| MEMORY_LINES.iter().all(|line| text.contains(line)));
    if !memory_ok {
        let mut message = "memory.x no longer describes 512 KiB flash at 0x08000000 and 128 KiB RAM at 0x20000000; update this check with it".to_string();
        if let Err(e) = memory {
            message.push_str(&format!(" ({e})"));
        }
        return Err(message);
    }
    let flash = format!("{}: {}", FLASH.0, FLASH.1);
    let ram = format!("{}: {}", RAM.0, RAM.1);

    let copy_file = format!("{COPY_DIR}/{chip}.yaml");
    if !root.join(&copy_file).is_file() {
        return Err(format!(
            "{copy_file} is missing: no copy of probe-rs's target description for {chip}, the chip the runners name (is the name right? the copy is the chip's entry in probe-rs/targets/ of the probe-rs sources)"
        ));
    }
    let bytes = std::fs::read(root.join(&copy_file)).map_err(|e| format!("{copy_file}: {e}"))?;
    let text =
        String::from_utf8(bytes).map_err(|e| format!("{copy_file}: not UTF-8 text ({e})"))?;
    let copy = parse_copy(&text, &copy_file)?;
    if copy.chip != chip {
        return Err(format!(
            "{copy_file} describes {}, not {chip} (the chip the runners name)",
            copy.chip
        ));
    }

    let (reported, source_line, place) = if installed("probe-rs") {
        let version_output = output(program("probe-rs").arg("--version"))?;
        let version = version_output.split('\n').next().unwrap_or_default();
        let chips = output(program("probe-rs").args(["chip", "list"]))?;
        let known = chips
            .split('\n')
            .any(|line| line.trim_start_matches(posix_space) == chip);
        if !known {
            return Err(format!(
                "probe-rs chip list ({version}) does not know {chip}"
            ));
        }
        let info = output(program("probe-rs").args(["chip", "info", &chip]))?;
        let reported = reported_lines(&info);
        let mut reported_sorted = reported.clone();
        reported_sorted.sort();
        let mut copy_sorted = copy.lines.clone();
        copy_sorted.sort();
        if reported_sorted != copy_sorted {
            return Err(format!(
                "{copy_file} no longer matches probe-rs's description of {chip} (differences, < probe-rs, > the copy):\n{}\nrefresh the copy from probe-rs/targets/ of the installed probe-rs version\nprobe-rs chip info {chip} ({version}):\n{}",
                differences(&reported_sorted, &copy_sorted),
                info.trim_end_matches('\n'),
            ));
        }
        (
            reported,
            format!(
                "checked against probe-rs itself ({version}: chip list and chip info), and {copy_file} agrees with it"
            ),
            format!("probe-rs chip info {chip}"),
        )
    } else {
        (
            copy.lines,
            format!(
                "checked against the copy of probe-rs's target description in {COPY_DIR} (probe-rs not installed)"
            ),
            copy_file,
        )
    };

    let regions = reported
        .iter()
        .filter(|line| {
            ["NVM:", "RAM:", "Generic:"]
                .iter()
                .any(|kind| line.starts_with(kind))
        })
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join("; ");
    if !reported.contains(&flash) {
        return Err(format!(
            "{place}: {chip} has no {} region {} (memory.x: 512K flash at 0x08000000); its regions: {regions}",
            FLASH.0, FLASH.1
        ));
    }
    if !reported.contains(&ram) {
        return Err(format!(
            "{place}: {chip} has no {} region {} (memory.x: 128K RAM at 0x20000000); its regions: {regions}",
            RAM.0, RAM.1
        ));
    }
    Ok(vec![
        source_line,
        format!(
            "{chip}: described by probe-rs, with 512 KiB flash at 0x08000000 and 128 KiB RAM at 0x20000000 as in memory.x"
        ),
    ])
}

/// The chip a Cargo configuration's runner names: NAME in every line
/// `runner = "probe-rs run --chip NAME"...` (NAME of ASCII letters, digits, `_`
/// and `-`, possibly empty), one a line, trailing empty lines dropped (as the
/// script's `sed` in a command substitution gives it); empty when none does.
fn runner_chip(config: &str) -> String {
    let names: Vec<&str> = config
        .split('\n')
        .filter_map(|line| {
            let rest = line.strip_prefix("runner")?.trim_start_matches(' ');
            let rest = rest.strip_prefix('=')?.trim_start_matches(' ');
            let rest = rest.strip_prefix("\"probe-rs run --chip ")?;
            let length = rest
                .bytes()
                .take_while(|b| b.is_ascii_alphanumeric() || *b == b'_' || *b == b'-')
                .count();
            rest[length..].starts_with('"').then(|| &rest[..length])
        })
        .collect();
    names.join("\n").trim_end_matches('\n').to_string()
}

/// The lines of `probe-rs chip info` that the copy is compared with (the
/// script's `sed`): `core: name (type)` lowercased for each line
/// ` - name (type)`, and `KIND: 0x...` `..0x...` for each line starting with
/// `NVM: `, `RAM: ` or `Generic: ` and a hexadecimal range (what follows the
/// range dropped).
fn reported_lines(info: &str) -> Vec<String> {
    info.split('\n')
        .filter_map(|line| core_line(line).or_else(|| region_line(line)))
        .collect()
}

/// `core: name (type)`, lowercased, for a line ` - name (type)`.
fn core_line(line: &str) -> Option<String> {
    let rest = line.trim_start_matches(' ').strip_prefix("- ")?;
    let body = rest.strip_suffix(')')?;
    let split = body.rfind(" (")?;
    Some(format!(
        "core: {} ({})",
        body[..split].to_lowercase(),
        body[split + 2..].to_lowercase()
    ))
}

/// `KIND: 0xSTART..0xEND` for a line starting with that (KIND one of `NVM`,
/// `RAM`, `Generic`; the hexadecimal digits possibly none).
fn region_line(line: &str) -> Option<String> {
    let (kind, rest) = ["NVM", "RAM", "Generic"].iter().find_map(|kind| {
        let rest = line.strip_prefix(kind)?.strip_prefix(": ")?;
        Some((kind, rest))
    })?;
    let hex_digits = |text: &str| text.bytes().take_while(u8::is_ascii_hexdigit).count();
    let start = rest.strip_prefix("0x")?;
    let start_digits = hex_digits(start);
    let end = start[start_digits..]
        .strip_prefix("..")?
        .strip_prefix("0x")?;
    let length = 2 + start_digits + 2 + 2 + hex_digits(end);
    Some(format!("{kind}: {}", &rest[..length]))
}

/// The differences between two sorted lists of lines, one a line: `< line`
/// for a line only `reported` has, `> line` for one only `copy` has.
fn differences(reported: &[String], copy: &[String]) -> String {
    let mut lines = Vec::new();
    let (mut r, mut c) = (0, 0);
    while r < reported.len() || c < copy.len() {
        match (reported.get(r), copy.get(c)) {
            (Some(a), Some(b)) if a == b => {
                r += 1;
                c += 1;
            }
            (Some(a), Some(b)) if a < b => {
                lines.push(format!("< {a}"));
                r += 1;
            }
            (_, Some(b)) => {
                lines.push(format!("> {b}"));
                c += 1;
            }
            (Some(a), None) => {
                lines.push(format!("< {a}"));
                r += 1;
            }
            (None, None) => break,
        }
    }
    lines.join("\n")
}

/// The copy of probe-rs's target description reduced to what
/// `probe-rs chip info` says.
#[derive(Debug, PartialEq, Eq)]
struct TargetCopy {
    /// The variant's (the chip's) name.
    chip: String,
    /// One line per core (`core: name (type)`, lowercased) and per memory
    /// region (`NVM: 0x08000000..0x08080000`), in the file's order.
    lines: Vec<String>,
}

/// A variant of the copy, as read so far.
struct Variant {
    /// Its name.
    name: String,
    /// Its cores: name and type (`None` until a `type:` line).
    cores: Vec<(String, Option<String>)>,
    /// Its memory regions.
    regions: Vec<Region>,
}

/// A memory region of a variant, as read so far.
struct Region {
    /// `NVM`, `RAM` or `Generic`.
    kind: &'static str,
    /// Its first address.
    start: Option<u128>,
    /// The address after its last.
    end: Option<u128>,
}

/// Reads `text`, a copy of probe-rs's target description (`path` names it in
/// errors), reading only the subset of YAML that probe-rs's target files use:
/// comments (from a `#` at the start of a line or after whitespace) are
/// dropped; top-level lines are the family's `name:`, `variants:` and a
/// variant's `- name:`; within a variant, a line indented by two that does not
/// start with `- ` opens a section; in `cores`, `- name:` starts a core and
/// `type:` gives the last one's type; in `memory_map`, `- !Nvm`, `- !Ram` and
/// `- !Generic` start a region and `start:` and `end:` (hexadecimal with `0x`,
/// or decimal) give the last one's bounds. There must be a family name and one
/// variant, with cores that all have types and regions that all have a start
/// before their end.
fn parse_copy(text: &str, path: &str) -> Result<TargetCopy, String> {
    let bad = |message: String| format!("{path}: {message}");
    // Python's universal newlines: `\r\n` and `\r` end lines too.
    let text = text.replace("\r\n", "\n").replace('\r', "\n");
    let mut family: Option<String> = None;
    let mut variants: Vec<Variant> = Vec::new();
    let mut section: Option<&str> = None;
    for (index, raw) in text.split('\n').enumerate() {
        let number = index + 1;
        let line = strip_comment(raw).trim_end_matches(py_space);
        if line.is_empty() {
            continue;
        }
        let text = line.trim_start_matches(py_space);
        let indent = line.chars().count() - text.chars().count();
        if indent == 0 {
            section = None;
            if let Some(rest) = text.strip_prefix("name:") {
                family = Some(py_strip(rest).to_string());
            } else if let Some(rest) = text.strip_prefix("- name:") {
                variants.push(Variant {
                    name: py_strip(rest).to_string(),
                    cores: Vec::new(),
                    regions: Vec::new(),
                });
            } else if text != "variants:" {
                return Err(bad(format!(
                    "line {number}: unexpected top-level line {}",
                    py_repr(text)
                )));
            }
            continue;
        }
        let Some(variant) = variants.last_mut() else {
            return Err(bad(format!(
                "line {number}: {} is outside a variant",
                py_repr(text)
            )));
        };
        if indent == 2 && !text.starts_with("- ") {
            section = text.split(':').next();
        } else if section == Some("cores") {
            if let Some(rest) = text.strip_prefix("- name:") {
                variant.cores.push((py_strip(rest).to_string(), None));
            } else if let Some(rest) = text.strip_prefix("type:") {
                if let Some(core) = variant.cores.last_mut() {
                    core.1 = Some(py_strip(rest).to_string());
                }
            }
        } else if section == Some("memory_map") {
            if let Some(kind) = region_kind(text) {
                variant.regions.push(Region {
                    kind,
                    start: None,
                    end: None,
                });
            } else if let Some((key, digits)) = bound(text) {
                if let Some(region) = variant.regions.last_mut() {
                    let value = number_value(digits).ok_or_else(|| {
                        bad(format!(
                            "line {number}: {} is not a number this check reads (hexadecimal after 0x, or decimal without leading zeros, below 2^128)",
                            py_repr(digits)
                        ))
                    })?;
                    if key == "start" {
                        region.start = Some(value);
                    } else {
                        region.end = Some(value);
                    }
                }
            }
        }
    }

    if family.as_deref().is_none_or(str::is_empty) {
        return Err(bad("no family name (top-level `name:`)".to_string()));
    }
    let variant = match <[Variant; 1]>::try_from(variants) {
        Ok([variant]) => variant,
        Err(variants) => {
            return Err(bad(format!(
                "expected one variant, found {}",
                variants.len()
            )))
        }
    };
    let name = &variant.name;
    if variant.cores.is_empty() || variant.cores.iter().any(|(_, kind)| kind.is_none()) {
        return Err(bad(format!("{name}: no cores, or a core without a type")));
    }
    if variant.regions.is_empty() {
        return Err(bad(format!("{name}: no memory regions")));
    }
    let mut lines = Vec::new();
    for (core, kind) in &variant.cores {
        let kind = kind.as_deref().unwrap_or_default();
        lines.push(format!(
            "core: {} ({})",
            core.to_lowercase(),
            kind.to_lowercase()
        ));
    }
    for region in &variant.regions {
        match (region.start, region.end) {
            (Some(start), Some(end)) if start < end => {
                lines.push(format!("{}: {start:#010x}..{end:#010x}", region.kind));
            }
            _ => {
                return Err(bad(format!(
                    "{name}: a {} region without a valid start..end range",
                    region.kind
                )))
            }
        }
    }
    Ok(TargetCopy {
        chip: variant.name,
        lines,
    })
}

/// `raw` without its comment: from the first `#` that starts the line or
/// follows whitespace (the Python `re.sub(r"(^|\s)#.*", "", raw)`).
fn strip_comment(raw: &str) -> &str {
    let mut previous: Option<(usize, char)> = None;
    for (index, c) in raw.char_indices() {
        if c == '#' {
            match previous {
                None => return "",
                Some((at, before)) if py_space(before) => return &raw[..at],
                Some(_) => {}
            }
        }
        previous = Some((index, c));
    }
    raw
}

/// The region kind a `memory_map` line `- !Nvm`, `- !Ram` or `- !Generic`
/// starts, as `probe-rs chip info` names it.
fn region_kind(text: &str) -> Option<&'static str> {
    match text {
        "- !Nvm" => Some("NVM"),
        "- !Ram" => Some("RAM"),
        "- !Generic" => Some("Generic"),
        _ => None,
    }
}

/// `start` or `end`, and the number, of a line `start: 0x8000000` or
/// `end: 524288` (spaces after the colon optional; the number hexadecimal
/// after `0x` or decimal); `None` for other lines.
fn bound(text: &str) -> Option<(&'static str, &str)> {
    let (key, rest) = if let Some(rest) = text.strip_prefix("start:") {
        ("start", rest)
    } else {
        ("end", text.strip_prefix("end:")?)
    };
    let digits = rest.trim_start_matches(' ');
    let number = match digits.strip_prefix("0x") {
        Some(hex) => !hex.is_empty() && hex.bytes().all(|b| b.is_ascii_hexdigit()),
        None => !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()),
    };
    number.then_some((key, digits))
}

/// The value of a number [`bound`] accepted, as Python's `int(digits, 0)`
/// reads it; `None` for a decimal number with leading zeros (which Python
/// refuses) or a number of 2^128 or more.
fn number_value(digits: &str) -> Option<u128> {
    match digits.strip_prefix("0x") {
        Some(hex) => u128::from_str_radix(hex, 16).ok(),
        None if digits.starts_with('0') => digits.bytes().all(|b| b == b'0').then_some(0),
        None => digits.parse().ok(),
    }
}

/// Whitespace as Python's `str.isspace` and regular expressions' `\s` see it
/// (Unicode whitespace, and the separators U+001C to U+001F).
fn py_space(c: char) -> bool {
    c.is_whitespace() || ('\u{1c}'..='\u{1f}').contains(&c)
}

/// `text` without leading and trailing whitespace (Python's `str.strip()`).
fn py_strip(text: &str) -> &str {
    text.trim_matches(py_space)
}

/// `text` as Python's `repr` writes a string, for messages.
fn py_repr(text: &str) -> String {
    let quote = if text.contains('\'') && !text.contains('"') {
        '"'
    } else {
        '\''
    };
    let mut repr = String::from(quote);
    for c in text.chars() {
        match c {
            '\\' => repr.push_str("\\\\"),
            '\t' => repr.push_str("\\t"),
            '\n' => repr.push_str("\\n"),
            '\r' => repr.push_str("\\r"),
            c if c == quote => {
                repr.push('\\');
                repr.push(c);
            }
            c if py_printable(c) => repr.push(c),
            c if u32::from(c) <= 0xff => repr.push_str(&format!("\\x{:02x}", u32::from(c))),
            c if u32::from(c) <= 0xffff => repr.push_str(&format!("\\u{:04x}", u32::from(c))),
            c => repr.push_str(&format!("\\U{:08x}", u32::from(c))),
        }
    }
    repr.push(quote);
    repr
}

/// Whether Python's `repr` writes `c` as it is: printable ASCII, or a
/// non-ASCII character that is not a control, format, surrogate, private-use,
/// unassigned or separator character (the characters Rust's `escape_debug`
/// also leaves alone, past a string's first).
fn py_printable(c: char) -> bool {
    if c.is_ascii() {
        (' '..='~').contains(&c)
    } else {
        let text = format!("a{c}");
        text.escape_debug().to_string() == text
    }
}

/// Whitespace as POSIX `[[:space:]]` sees it in ASCII.
fn posix_space(c: char) -> bool {
    matches!(c, ' ' | '\t' | '\n' | '\u{b}' | '\u{c}' | '\r')
}

#[cfg(test)]
mod tests {
    use super::*;

    const PATH: &str = "copy.yaml";

    fn lines(lines: &[&str]) -> Vec<String> {
        lines.iter().map(|line| line.to_string()).collect()
    }

    fn parse_error(text: &str) -> String {
        match parse_copy(text, PATH) {
            Ok(copy) => panic!("parsed {copy:?}"),
            Err(message) => message,
        }
    }

    const SMALL: &str = "\
name: Family
variants:
- name: CHIP1
  cores:
  - name: Main
    type: ArmV7EM
  memory_map:
  - !Nvm
    range:
      start: 0x8000000
      end: 0x8080000
  - !Ram
    range:
      start: 536870912
      end: 0x20020000
";

    #[test]
    fn the_checked_in_copy_reads_as_probe_rs_describes_the_chip() {
        let path = format!("{COPY_DIR}/STM32F411CE.yaml");
        let text = std::fs::read_to_string(repo_root().join(&path)).expect("the checked-in copy");
        let copy = parse_copy(&text, &path).expect("the checked-in copy parses");
        assert_eq!(copy.chip, "STM32F411CE");
        assert_eq!(
            copy.lines,
            lines(&[
                "core: main (armv7em)",
                "NVM: 0x08000000..0x08080000",
                "NVM: 0x1fff7800..0x1fff7a10",
                "RAM: 0x20000000..0x20020000",
            ])
        );
        assert!(copy.lines.contains(&format!("{}: {}", FLASH.0, FLASH.1)));
        assert!(copy.lines.contains(&format!("{}: {}", RAM.0, RAM.1)));
    }

    #[test]
    fn a_small_copy_reads_with_comments_other_sections_and_crlf() {
        let copy = parse_copy(SMALL, PATH).expect("parses");
        assert_eq!(copy.chip, "CHIP1");
        assert_eq!(
            copy.lines,
            lines(&[
                "core: main (armv7em)",
                "NVM: 0x08000000..0x08080000",
                "RAM: 0x20000000..0x20020000",
            ])
        );
        let commented = "# a comment\n\
            name: Family # trailing\n\
            variants:\n\
            - name: CHIP#2\n  \
              package_variants:\n  \
              - name: not-a-core\n  \
              cores:  # the cores\n  \
              - name: main\n    \
                type:\tarmv6m\n  \
              memory_map:\n  \
              - !Generic # a generic region\n    \
                start:   0x10\n    \
                end: 32\n"
            .replace('\n', "\r\n");
        let copy = parse_copy(&commented, PATH).expect("parses");
        assert_eq!(copy.chip, "CHIP#2");
        assert_eq!(
            copy.lines,
            lines(&["core: main (armv6m)", "Generic: 0x00000010..0x00000020"])
        );
    }

    #[test]
    fn malformed_copies_are_refused_naming_the_line() {
        assert_eq!(
            parse_error("name: F\nvariants:\nbogus: 1\n"),
            "copy.yaml: line 3: unexpected top-level line 'bogus: 1'"
        );
        assert_eq!(
            parse_error("name: F\n\n# comment\nit's: \"quoted\"\\\n"),
            "copy.yaml: line 4: unexpected top-level line 'it\\'s: \"quoted\"\\\\'"
        );
        assert_eq!(
            parse_error("name: F\nvariants:\n  - name: X\n"),
            "copy.yaml: line 3: '- name: X' is outside a variant"
        );
        assert_eq!(
            parse_error(&SMALL.replace("end: 0x20020000", "end: 0020020000")),
            "copy.yaml: line 15: '0020020000' is not a number this check reads (hexadecimal after 0x, or decimal without leading zeros, below 2^128)"
        );
    }

    #[test]
    fn incomplete_copies_are_refused() {
        assert_eq!(
            parse_error(&SMALL.replace("name: Family", "name:")),
            "copy.yaml: no family name (top-level `name:`)"
        );
        assert_eq!(
            parse_error(&format!("{SMALL}- name: CHIP2\n")),
            "copy.yaml: expected one variant, found 2"
        );
        assert_eq!(
            parse_error("name: F\nvariants:\n"),
            "copy.yaml: expected one variant, found 0"
        );
        assert_eq!(
            parse_error(&SMALL.replace("    type: ArmV7EM\n", "")),
            "copy.yaml: CHIP1: no cores, or a core without a type"
        );
        assert_eq!(
            parse_error(
                &SMALL
                    .replace("- !Nvm", "- !Flash")
                    .replace("- !Ram", "- !Rom")
            ),
            "copy.yaml: CHIP1: no memory regions"
        );
        assert_eq!(
            parse_error(&SMALL.replace("      end: 0x8080000\n", "")),
            "copy.yaml: CHIP1: a NVM region without a valid start..end range"
        );
        assert_eq!(
            parse_error(&SMALL.replace("end: 0x20020000", "end: 0x20000000")),
            "copy.yaml: CHIP1: a RAM region without a valid start..end range"
        );
    }

    #[test]
    fn runner_chips_read_as_the_script_reads_them() {
        let config = "[target.thumbv7em-none-eabihf]\nrunner = \"probe-rs run --chip STM32F411CE\" # board\n";
        assert_eq!(runner_chip(config), "STM32F411CE");
        assert_eq!(
            runner_chip("runner=\"probe-rs run --chip A_b-1\"\n"),
            "A_b-1"
        );
        assert_eq!(runner_chip(" runner = \"probe-rs run --chip X\"\n"), "");
        assert_eq!(runner_chip("runner = \"probe-rs run --chip X.Y\"\n"), "");
        assert_eq!(runner_chip("runner = \"probe-rs run --chip \"\n"), "");
        assert_eq!(
            runner_chip("runner = \"probe-rs run --chip A\"\nrunner = \"probe-rs run --chip B\"\n"),
            "A\nB"
        );
    }

    #[test]
    fn chip_info_reduces_to_cores_and_regions() {
        let info = "\
STM32F411CE
Cores (1):
    - main (Armv7em)
    - Second Core (armv6m) (ARMv8M)
NVM: 0x08000000..0x08080000 (512.00 KiB)
NVM: 0x1fff7800..0x1fff7a10 (528 B)
RAM: 0x20000000..0x20020000 (128.00 KiB)
Generic: 0x..0x1
RAM 0x1..0x2
";
        assert_eq!(
            reported_lines(info),
            lines(&[
                "core: main (armv7em)",
                "core: second core (armv6m) (armv8m)",
                "NVM: 0x08000000..0x08080000",
                "NVM: 0x1fff7800..0x1fff7a10",
                "RAM: 0x20000000..0x20020000",
                "Generic: 0x..0x1",
            ])
        );
    }

    #[test]
    fn differences_name_each_side() {
        let reported = lines(&["a", "b", "d"]);
        let copy = lines(&["a", "c", "d", "e"]);
        assert_eq!(differences(&reported, &copy), "< b\n> c\n> e");
    }

    #[test]
    fn comments_and_reprs_follow_python() {
        assert_eq!(strip_comment("# all"), "");
        assert_eq!(strip_comment("a # b"), "a");
        assert_eq!(strip_comment("a#b # c"), "a#b");
        assert_eq!(strip_comment("a\u{a0}#b"), "a");
        assert_eq!(py_repr("a'b"), "\"a'b\"");
        assert_eq!(py_repr("\u{7}é\u{a0}\u{200b}"), "'\\x07é\\xa0\\u200b'");
    }
}
