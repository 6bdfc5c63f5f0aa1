//! Building the QEMU firmware for a configuration and running it.
//!
//! The firmware (`firmware/qemu`) bakes its scene and buffer parameters in at build
//! time, so every configuration is its own build. A run writes `frame-NNN.ppm` and
//! `stats.csv` through semihosting into a work folder; this module reads them back.

use mcu_abuffer::memory::defaults;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Builds in the QEMU firmware's target folder must not overlap: a build replaces
/// the ELF the previous one produced. (The board firmware has its own folder and
/// lock, so a board build and a QEMU build can run side by side.)
static QEMU_BUILD_LOCK: Mutex<()> = Mutex::new(());
/// [`QEMU_BUILD_LOCK`] for the board firmware's target folder.
static BOARD_BUILD_LOCK: Mutex<()> = Mutex::new(());

/// The repository root (where `firmware/` is).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// What a firmware build carries.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FirmwareConfig {
    /// Built-in scene name or scene file (relative to the repository root).
    pub scene: String,
    /// Turntable frames.
    pub frames: u32,
    /// `split-bands`, `shared`, `merge-closest`, `fixed-discard`, `fixed-merge`,
    /// `unlimited` or `zbuffer`.
    pub method: String,
    /// `4x4`, `8x4` or `8x8`.
    pub grid: String,
    /// Band height.
    pub band: u16,
    /// `N_main`.
    pub main: u8,
    /// `N_extra`.
    pub extra: u8,
    /// `N_pool`.
    pub pool: usize,
    /// `N_fixed`.
    pub fixed: u8,
}

impl Default for FirmwareConfig {
    /// The default M4 configuration (the firmware build script's defaults:
    /// `split-bands` and the library's `memory::defaults`; a configuration
    /// for another method takes its band from [`FirmwareConfig::for_method`]).
    fn default() -> Self {
        Self {
            scene: "teapot".into(),
            frames: 4,
            method: "split-bands".into(),
            grid: "4x4".into(),
            band: defaults::BAND_ROWS,
            main: defaults::MAIN_SLOTS,
            extra: defaults::EXTRA_ADDRESSES,
            pool: defaults::POOL_SLOTS,
            fixed: defaults::FIXED_SLOTS,
        }
    }
}

impl FirmwareConfig {
    /// The default configuration for `method`, with the method's default band
    /// height (`memory::defaults::band_rows`: taller for the z-buffer).
    pub fn for_method(method: &str) -> Self {
        Self {
            method: method.into(),
            band: defaults::band_rows(method == "zbuffer"),
            ..Self::default()
        }
    }

    /// The build script's environment for this configuration.
    pub fn env(&self) -> Vec<(&'static str, String)> {
        vec![
            ("FIRMWARE_SCENE", self.scene.clone()),
            ("FIRMWARE_FRAMES", self.frames.to_string()),
            ("FIRMWARE_METHOD", self.method.clone()),
            ("FIRMWARE_GRID", self.grid.clone()),
            ("FIRMWARE_BAND", self.band.to_string()),
            ("FIRMWARE_MAIN", self.main.to_string()),
            ("FIRMWARE_EXTRA", self.extra.to_string()),
            ("FIRMWARE_POOL", self.pool.to_string()),
            ("FIRMWARE_FIXED", self.fixed.to_string()),
        ]
    }

    /// The turntable angle of frame `i`, in degrees, exactly as the firmware's
    /// build script computes it (so host renderings use the same bits).
    pub fn frame_angle(&self, i: u32) -> f32 {
        360.0 * i as f32 / self.frames.max(1) as f32
    }
}

/// Which QEMU firmware binary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FirmwareTarget {
    /// `qemu-m4` for `mps2-an386` (Cortex-M4F, `thumbv7em-none-eabihf`).
    M4,
    /// `qemu-oled` for `lm3s6965evb` (Cortex-M3, `thumbv7m-none-eabi`).
    Oled,
}

impl FirmwareTarget {
    fn bin(self) -> &'static str {
        match self {
            Self::M4 => "qemu-m4",
            Self::Oled => "qemu-oled",
        }
    }

    fn triple(self) -> &'static str {
        match self {
            Self::M4 => "thumbv7em-none-eabihf",
            Self::Oled => "thumbv7m-none-eabi",
        }
    }

    fn feature(self) -> &'static str {
        match self {
            Self::M4 => "m4",
            Self::Oled => "oled",
        }
    }
}

/// Whether a firmware build keeps the debug information its release profile asks
/// for.
///
/// Running, counting and size checks need none of it, and it costs about a third
/// of each fat-LTO build (the tests build a dozen firmwares). The per-function
/// profile needs it: `scripts/qemu-profile.py` attributes instructions to inlined
/// functions and source lines through it. The generated code differs slightly
/// between the two (teapot, frame 0: 23,919,809 instructions without, 23,902,440
/// with), so exact counts are compared between builds of the same kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DebugInfo {
    /// As the workspace's release profile says (full debug information).
    Kept,
    /// Left out (`CARGO_PROFILE_RELEASE_DEBUG=0`).
    Dropped,
}

impl DebugInfo {
    /// The variable that overrides the release profile's debug information.
    const VARIABLE: &'static str = "CARGO_PROFILE_RELEASE_DEBUG";

    /// Sets up `cargo` (a release build, or the lints of one) for this choice.
    pub fn apply_to(self, cargo: &mut Command) -> &mut Command {
        match self {
            Self::Kept => cargo.env_remove(Self::VARIABLE),
            Self::Dropped => cargo.env(Self::VARIABLE, "0"),
        }
    }
}

/// Builds the M4 firmware for `config` and copies the ELF to `dest`, without debug
/// information.
///
/// Errors carry the build's own message (for example a configuration that does not
/// fit the board's RAM).
pub fn build_m4(config: &FirmwareConfig, features: &[&str], dest: &Path) -> Result<(), String> {
    build_firmware(FirmwareTarget::M4, config, features, dest)
}

/// Builds the M4 firmware for `config` with its debug information (for the
/// per-function profile) and copies the ELF to `dest`.
pub fn build_m4_with_debug_info(config: &FirmwareConfig, dest: &Path) -> Result<(), String> {
    let target = FirmwareTarget::M4;
    build_qemu_firmware(target, target.bin(), config, &[], DebugInfo::Kept, dest)
}

/// Builds a firmware binary for `config` with extra `features`, without debug
/// information, and copies the ELF to `dest`.
pub fn build_firmware(
    target: FirmwareTarget,
    config: &FirmwareConfig,
    features: &[&str],
    dest: &Path,
) -> Result<(), String> {
    build_firmware_bin(target, target.bin(), config, features, dest)
}

/// Builds binary `bin` of the QEMU firmware workspace for `target`'s machine
/// (for example `qemu-stack-overflow` for the M4), without debug information, and
/// copies the ELF to `dest`.
pub fn build_firmware_bin(
    target: FirmwareTarget,
    bin: &str,
    config: &FirmwareConfig,
    features: &[&str],
    dest: &Path,
) -> Result<(), String> {
    build_qemu_firmware(target, bin, config, features, DebugInfo::Dropped, dest)
}

/// [`build_firmware_bin`] with the choice of debug information.
fn build_qemu_firmware(
    target: FirmwareTarget,
    bin: &str,
    config: &FirmwareConfig,
    features: &[&str],
    debug_info: DebugInfo,
    dest: &Path,
) -> Result<(), String> {
    let _guard = QEMU_BUILD_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let root = repo_root();
    let mut all_features = vec![target.feature()];
    all_features.extend_from_slice(features);
    let features = all_features.join(",");
    let args = [
        "--no-default-features",
        "--bin",
        bin,
        "--target",
        target.triple(),
        "--features",
        &features,
    ];
    cargo_build_in(
        &root.join("firmware/qemu"),
        &args,
        &config.env(),
        debug_info,
    )?;
    let elf = root
        .join("firmware/qemu/target")
        .join(target.triple())
        .join("release")
        .join(bin);
    std::fs::copy(&elf, dest).map_err(|e| format!("{}: {e}", elf.display()))?;
    Ok(())
}

/// Runs `cargo build --release` in the firmware workspace `dir` with `args` and the
/// environment `env`, keeping the caller's target folder and flags out of it. A
/// failure returns the build's error lines (the build scripts' "does not fit"
/// messages included).
fn cargo_build_in<K: AsRef<std::ffi::OsStr>>(
    dir: &Path,
    args: &[&str],
    env: &[(K, String)],
    debug_info: DebugInfo,
) -> Result<(), String> {
    let mut cmd = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cmd.args(["build", "--release", "--quiet"])
        .args(args)
        .arg("--manifest-path")
        .arg(dir.join("Cargo.toml"))
        .current_dir(dir);
    for (k, v) in env {
        cmd.env(k, v);
    }
    debug_info.apply_to(&mut cmd);
    // Each firmware has its own target folder; keep outer settings out of it.
    cmd.env_remove("CARGO_TARGET_DIR")
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET");
    let out = cmd.output().map_err(|e| format!("cannot run cargo: {e}"))?;
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let reason = stderr
            .lines()
            .filter(|l| l.starts_with("error") || l.contains("does not fit"))
            .collect::<Vec<_>>()
            .join("\n");
        let hint = if stderr.contains("linker `flip-link` not found") {
            "\nthe firmwares link through flip-link: cargo install flip-link"
        } else {
            ""
        };
        return Err(if reason.is_empty() {
            format!("{stderr}{hint}")
        } else {
            format!("{reason}{hint}")
        });
    }
    Ok(())
}

/// Builds the STM32F411 board firmware (`firmware/blackpill`) with the `BOARD_*`
/// variables in `env`, without debug information, and copies the ELF to `dest`.
pub fn build_board(env: &[(&str, String)], dest: &Path) -> Result<(), String> {
    let _guard = BOARD_BUILD_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let dir = repo_root().join("firmware/blackpill");
    let args = ["--target", "thumbv7em-none-eabihf"];
    cargo_build_in(&dir, &args, env, DebugInfo::Dropped)?;
    let elf = dir.join("target/thumbv7em-none-eabihf/release/blackpill-st7789");
    std::fs::copy(&elf, dest).map_err(|e| format!("{}: {e}", elf.display()))?;
    Ok(())
}

/// One frame's statistics as the firmware wrote them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FirmwareFrameStats {
    /// Frame index.
    pub frame: u64,
    /// Instructions for the whole frame (SysTick ticks x 40).
    pub instructions: u64,
    /// Of those, instructions spent writing the frame to the host.
    pub output_instructions: u64,
    /// Fragments generated.
    pub generated: u64,
    /// Fragments stored.
    pub stored: u64,
    /// New fragments hidden on arrival.
    pub hidden_on_arrival: u64,
    /// Stored fragments removed as hidden.
    pub removed_hidden: u64,
    /// Merges.
    pub merges: u64,
    /// Fragments discarded.
    pub discarded: u64,
    /// Pool peak.
    pub pool_peak: u64,
    /// Most fragments in one pixel.
    pub max_in_pixel: u64,
    /// Triangles in the scene.
    pub triangles: u64,
    /// The stack's high-water mark since reset, in bytes, after this frame (0
    /// from a firmware that does not report it).
    pub stack_peak: u64,
}

/// What a firmware run left behind.
#[derive(Clone, Debug, Default)]
pub struct FirmwareRun {
    /// Per-frame statistics.
    pub stats: Vec<FirmwareFrameStats>,
    /// RGB888 frames, rows top to bottom.
    pub frames: Vec<Vec<u8>>,
    /// Frame width and height.
    pub size: (u32, u32),
    /// The raw defmt stream from QEMU's standard output.
    pub defmt: Vec<u8>,
}

fn parse_ppm(bytes: &[u8]) -> Result<((u32, u32), Vec<u8>), String> {
    // "P6\n<w> <h>\n255\n" then binary RGB.
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 && i < bytes.len() {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        let start = i;
        while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        fields.push(String::from_utf8_lossy(&bytes[start..i]).into_owned());
    }
    if fields.len() < 4 || fields[0] != "P6" || fields[3] != "255" {
        return Err("not a binary 8-bit PPM".into());
    }
    let w: u32 = fields[1].parse().map_err(|_| "bad PPM width")?;
    let h: u32 = fields[2].parse().map_err(|_| "bad PPM height")?;
    let data = bytes.get(i + 1..).ok_or("PPM without pixels")?;
    if data.len() != (w * h * 3) as usize {
        return Err(format!(
            "PPM has {} bytes of pixels, {w}x{h} needs {}",
            data.len(),
            w * h * 3
        ));
    }
    Ok(((w, h), data.to_vec()))
}

/// Runs an M4 firmware ELF under QEMU (`mps2-an386`, `-icount shift=0`) in `workdir`
/// and reads back its frames and statistics. Fails on a non-zero exit or a time-out.
pub fn run_m4(elf: &Path, workdir: &Path, timeout: Duration) -> Result<FirmwareRun, String> {
    std::fs::create_dir_all(workdir).map_err(|e| format!("{}: {e}", workdir.display()))?;
    let defmt_path = workdir.join("defmt.bin");
    let defmt_file = std::fs::File::create(&defmt_path).map_err(|e| e.to_string())?;
    let mut child = Command::new("qemu-system-arm")
        .args([
            "-M",
            "mps2-an386",
            "-cpu",
            "cortex-m4",
            "-nographic",
            "-monitor",
            "none",
            "-serial",
            "none",
        ])
        .args([
            "-semihosting-config",
            "enable=on,target=native",
            "-icount",
            "shift=0",
            "-kernel",
        ])
        .arg(elf)
        .current_dir(workdir)
        .stdin(Stdio::null())
        .stdout(defmt_file)
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!(
                "cannot start qemu-system-arm (install the Debian package qemu-system-arm): {e}"
            )
        })?;
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "QEMU did not finish within {} s",
                timeout.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    if !status.success() {
        return Err(format!("firmware exited with {status}: {stderr}"));
    }
    let csv = std::fs::read_to_string(workdir.join("stats.csv"))
        .map_err(|e| format!("stats.csv: {e}"))?;
    let mut stats = Vec::new();
    for line in csv.lines().skip(1) {
        let v: Vec<u64> = line
            .split(',')
            .map(|f| f.trim().parse().unwrap_or(0))
            .collect();
        if v.len() < 12 {
            return Err(format!("stats.csv: short line '{line}'"));
        }
        stats.push(FirmwareFrameStats {
            frame: v[0],
            instructions: v[1],
            output_instructions: v[2],
            generated: v[3],
            stored: v[4],
            hidden_on_arrival: v[5],
            removed_hidden: v[6],
            merges: v[7],
            discarded: v[8],
            pool_peak: v[9],
            max_in_pixel: v[10],
            triangles: v[11],
            // Columns after the ones above are optional; more are ignored.
            stack_peak: v.get(12).copied().unwrap_or(0),
        });
    }
    let mut frames = Vec::new();
    let mut size = (0, 0);
    for i in 0..stats.len() {
        let path = workdir.join(format!("frame-{i:03}.ppm"));
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let (s, rgb) = parse_ppm(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        size = s;
        frames.push(rgb);
    }
    let defmt = std::fs::read(&defmt_path).unwrap_or_default();
    Ok(FirmwareRun {
        stats,
        frames,
        size,
        defmt,
    })
}

/// Decodes a defmt stream with `defmt-print` (if installed) for display.
pub fn decode_defmt(elf: &Path, stream: &[u8]) -> Option<String> {
    use std::io::Write;
    let mut child = Command::new("defmt-print")
        .arg("-e")
        .arg(elf)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .ok()?;
    child.stdin.take()?.write_all(stream).ok()?;
    let out = child.wait_with_output().ok()?;
    Some(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// Runs the OLED firmware under QEMU (`lm3s6965evb`, no display window), waits for
/// it to report the frame out, takes a screendump over QMP and returns the display
/// as 4-bit gray levels, `width x height` (the SSD0323's 128 x 64 by default).
pub fn run_oled_screendump(
    elf: &Path,
    workdir: &Path,
    timeout: Duration,
) -> Result<Vec<u8>, String> {
    use std::io::{BufRead, BufReader, Read, Write};
    use std::os::unix::net::UnixStream;
    std::fs::create_dir_all(workdir).map_err(|e| format!("{}: {e}", workdir.display()))?;
    let socket = workdir.join("qmp.sock");
    let _ = std::fs::remove_file(&socket);
    let mut child = Command::new("qemu-system-arm")
        .args([
            "-M",
            "lm3s6965evb",
            "-display",
            "none",
            "-monitor",
            "none",
            "-serial",
            "none",
        ])
        .arg("-qmp")
        .arg(format!("unix:{},server=on,wait=off", socket.display()))
        .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
        .arg(elf)
        .current_dir(workdir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start qemu-system-arm: {e}"))?;
    let result = (|| -> Result<Vec<u8>, String> {
        // Wait for "frame done" on the semihosting console (QEMU's stdout).
        let stdout = child.stdout.take().ok_or("no stdout")?;
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            // The console carries binary defmt frames too: read bytes, not text.
            let mut seen = Vec::new();
            let mut reader = BufReader::new(stdout);
            let mut chunk = Vec::new();
            while reader.read_until(b'\n', &mut chunk).unwrap_or(0) > 0 {
                seen.extend_from_slice(&chunk);
                if chunk.windows(10).any(|w| w == b"frame done") {
                    let _ = tx.send(Ok(()));
                    return;
                }
                chunk.clear();
            }
            let _ = tx.send(Err(String::from_utf8_lossy(&seen).into_owned()));
        });
        match rx.recv_timeout(timeout) {
            Ok(Ok(())) => {}
            Ok(Err(text)) => {
                // QEMU closed its console: it has exited; collect what it said.
                let _ = child.kill();
                let mut err = String::new();
                if let Some(mut e) = child.stderr.take() {
                    let _ = e.read_to_string(&mut err);
                }
                return Err(format!(
                    "firmware stopped before the frame was out: {text} {err}"
                ));
            }
            Err(_) => return Err(format!("no frame within {} s", timeout.as_secs())),
        }
        let stream = UnixStream::connect(&socket).map_err(|e| format!("QMP socket: {e}"))?;
        stream
            .set_read_timeout(Some(Duration::from_secs(30)))
            .map_err(|e| e.to_string())?;
        let mut writer = stream.try_clone().map_err(|e| e.to_string())?;
        let mut reader = BufReader::new(stream);
        let mut line = String::new();
        reader
            .read_line(&mut line)
            .map_err(|e| format!("QMP greeting: {e}"))?;
        let dump = workdir.join("screendump.ppm");
        let commands = [
            r#"{"execute":"qmp_capabilities"}"#.to_string(),
            format!(
                r#"{{"execute":"screendump","arguments":{{"filename":"{}"}}}}"#,
                dump.display()
            ),
        ];
        for c in commands {
            writer
                .write_all(c.as_bytes())
                .and_then(|_| writer.write_all(b"\n"))
                .map_err(|e| e.to_string())?;
            loop {
                line.clear();
                reader
                    .read_line(&mut line)
                    .map_err(|e| format!("QMP: {e}"))?;
                if line.contains("\"error\"") {
                    return Err(format!("QMP: {line}"));
                }
                if line.contains("\"return\"") {
                    break;
                }
            }
        }
        let _ = writer.write_all(b"{\"execute\":\"quit\"}\n");
        let bytes = std::fs::read(&dump).map_err(|e| format!("{}: {e}", dump.display()))?;
        let ((w, h), rgb) = parse_ppm(&bytes)?;
        screendump_to_gray4(w, h, &rgb)
    })();
    let _ = child.kill();
    let _ = child.wait();
    result
}

/// QEMU shows the SSD0323 magnified 4 times, level `l` as the gray `l * 17`.
/// Returns the levels, checking that every 4 x 4 block is one level.
pub fn screendump_to_gray4(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    const MAGNIFY: u32 = 4;
    let (w, h) = (width / MAGNIFY, height / MAGNIFY);
    let mut levels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let at = |dx: u32, dy: u32| {
                let i = (((y * MAGNIFY + dy) * width + x * MAGNIFY + dx) * 3) as usize;
                (rgb[i], rgb[i + 1], rgb[i + 2])
            };
            let first = at(0, 0);
            for dy in 0..MAGNIFY {
                for dx in 0..MAGNIFY {
                    if at(dx, dy) != first {
                        return Err(format!("screendump block ({x}, {y}) is not one color"));
                    }
                }
            }
            let (r, g, b) = first;
            if r != g || g != b || r % 17 != 0 {
                return Err(format!(
                    "screendump pixel ({x}, {y}) = {first:?} is not a 4-bit gray"
                ));
            }
            levels.push(r / 17);
        }
    }
    Ok(levels)
}
