//! The reference images and the measured results in `docs/`, regenerated with
//! the release build of `host-sim` (built once per task):
//!
//! - [`reference_images`]: the reference renderings of the three built-in
//!   scenes in `docs/images/` and their statistics (a few seconds);
//! - [`shading_images`]: the shading comparisons `docs/images/shading-*`
//!   (a few seconds);
//! - [`zbuffer_table`]: the tables and images of the section "Z-buffer with
//!   midpoint subdivision" of `docs/results.md` (about two minutes on a 2-core
//!   machine with the default 9 timings);
//! - [`results`]: everything else in `docs/results/` that `docs/results.md`
//!   reports (about three minutes on a 2-core machine).
//!
//! Every program runs in the repository root, so the paths given to `host-sim`
//! are relative to it. Where the output of a program is not wanted it is
//! discarded, where it is a result it is written to its file; the programs'
//! errors always reach the terminal.

use crate::run::{create_dir, describe, host_sim_release, program, repo_root, scratch_dir, status};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Where the reference renderings and the shading comparisons go.
const IMAGES: &str = "docs/images";
/// Where the results reported by `docs/results.md` go.
const OUT: &str = "docs/results";

/// Regenerates the reference renderings in `docs/images/` and their statistics
/// (`docs/images/*.json`): the three built-in scenes at 240x240 with
/// `unlimited`, `split-bands` (the default), `shared` (1 main slot, 2 pool
/// addresses, the default pool) and `zbuffer`. Takes a few seconds.
pub fn reference_images() -> Result<(), String> {
    let hs = host_sim_release()?;
    create_dir(&repo_root().join(IMAGES))?;
    for scene in ["teapot", "spheres", "starfighter"] {
        for method in ["unlimited", "split-bands", "shared", "zbuffer"] {
            discard(program(&hs).args([
                "render",
                "--scene",
                scene,
                "--method",
                method,
                "--out",
                &format!("{IMAGES}/{scene}-{method}.png"),
                "--stats-json",
                &format!("{IMAGES}/{scene}-{method}.json"),
            ]))?;
        }
    }
    println!("wrote {IMAGES}/");
    Ok(())
}

/// Regenerates the shading comparisons in `docs/images/shading-*.png` and
/// their numbers (`docs/images/shading-*.json`): gouraud | quadratic | phong |
/// error of gouraud | error of quadratic, for one lit sphere
/// (`docs/scenes/sphere.toml`) and for the teapot. Takes a few seconds.
pub fn shading_images() -> Result<(), String> {
    let hs = host_sim_release()?;
    create_dir(&repo_root().join(IMAGES))?;
    for scene in ["docs/scenes/sphere.toml", "teapot"] {
        // The scene file's name without its folder and `.toml`, as `basename`.
        let name = Path::new(scene)
            .file_name()
            .and_then(|n| n.to_str())
            .map_or(scene, |n| n.strip_suffix(".toml").unwrap_or(n));
        status(program(&hs).args([
            "shading",
            "--scene",
            scene,
            "--out",
            &format!("{IMAGES}/shading-{name}.png"),
            "--stats-json",
            &format!("{IMAGES}/shading-{name}.json"),
        ]))?;
    }
    Ok(())
}

/// Regenerates the tables and images of the section "Z-buffer with midpoint
/// subdivision" in `docs/results.md` (`docs/results/zbuffer-*`): depth
/// comparisons, time per frame and pixels differing from the plain z-buffer
/// for `zbuffer`, `zbuffer-hiz` and `zbuffer-midpoint` (K = 0..3, as published
/// and with per-pixel tests kept), at 800x600 on the built-in scene `overdraw`
/// (one band for the whole frame, and bands of 16 rows) and on the teapot.
///
/// Times are the host's processor time per frame, the fastest of `repeat`
/// timings of at least 5 renders and 100 ms each, the configurations taking
/// turns (the published tables use 9); the counters are exact and the same
/// on every run. Takes about two minutes on a 2-core machine with
/// `repeat` = 9.
pub fn zbuffer_table(repeat: u32) -> Result<(), String> {
    let hs = host_sim_release()?;
    let repeat = repeat.to_string();
    create_dir(&repo_root().join(OUT))?;
    let tmp = scratch_dir("zbuffer-table")?;

    for (extra, name) in [
        (&["--scene", "overdraw"][..], "zbuffer-overdraw"),
        (
            &["--scene", "overdraw", "--band", "16"][..],
            "zbuffer-overdraw-band16",
        ),
        (&["--scene", "teapot"][..], "zbuffer-teapot"),
    ] {
        status(program(&hs).arg("zbuffer-table").args(extra).args([
            "--repeat",
            &repeat,
            "--out",
            &format!("{OUT}/{name}.md"),
        ]))?;
    }

    // Where the published setting (K = 2, visible pieces not tested) goes
    // wrong: the differences from the plain z-buffer, as published and with
    // the per-pixel tests kept.
    let size = [
        "--scene", "overdraw", "--width", "800", "--height", "600", "--band", "600",
    ];
    let zbuffer = format!("{OUT}/zbuffer-overdraw.png");
    let midpoint = tmp.path().join("midpoint.png");
    let safe = tmp.path().join("safe.png");
    discard(
        program(&hs)
            .arg("render")
            .args(size)
            .args(["--method", "zbuffer", "--out", &zbuffer]),
    )?;
    discard(
        program(&hs)
            .arg("render")
            .args(size)
            .args(["--method", "zbuffer-midpoint", "--out"])
            .arg(&midpoint),
    )?;
    discard(
        program(&hs)
            .arg("render")
            .args(size)
            .args(["--method", "zbuffer-midpoint", "--midpoint-safe", "--out"])
            .arg(&safe),
    )?;
    for (image, diff) in [
        (&midpoint, "zbuffer-midpoint-k2-diff"),
        (&safe, "zbuffer-midpoint-k2-safe-diff"),
    ] {
        status(program(&hs).arg("compare").arg(image).arg(&zbuffer).args([
            "--diff",
            &format!("{OUT}/{diff}.png"),
            "--diff-scale",
            "64",
        ]))?;
    }
    Ok(())
}

/// The image size of the results.
const SIZE: [&str; 4] = ["--width", "240", "--height", "240"];
/// The tables in `docs/results.md` were measured with 16-row bands, not the
/// library's default (`memory::defaults::BAND_ROWS`): the band is given
/// explicitly wherever it changes a figure.
const BAND: [&str; 2] = ["--band", "16"];
/// The three test objects.
const OBJECTS: [&str; 3] = ["starfighter", "teapot:24", "knot"];
/// Frames of the sweeps' turntables.
const FRAMES: &str = "12";
/// The synthetic scene: layers of depth complexity 6.
const LAYERS: &str = "layers:1000:6:1";

/// Regenerates everything in `docs/results/` that `docs/results.md` reports:
/// the sweeps (CSV, Markdown summary, NMSE plots) of the three test objects
/// and a synthetic scene, the supersampling comparison table, depth-complexity
/// statistics and heat maps, difference heat maps, bounded-memory and tuning
/// tables, and a turntable animation. Takes about three minutes on a 2-core
/// machine. Section numbers in the comments refer to `docs/results.md`.
pub fn results() -> Result<(), String> {
    let host_sim = host_sim_release()?;
    let hs = || program(&host_sim);
    let root = repo_root();
    create_dir(&root.join(OUT))?;
    let tmp = scratch_dir("results")?;
    let tmp = tmp.path();

    // Sections 1, 2 and 4: every policy at 1..8 fragments per pixel over a
    // 12-frame turntable; the pool of shared and merge-closest is the worst
    // peak over the frames. The synthetic layers of depth complexity 6 are
    // section 1's controlled complexity.
    for s in OBJECTS.into_iter().chain([LAYERS]) {
        discard(
            hs().args(["sweep", "--scene", s])
                .args(SIZE)
                .args(BAND)
                .args(["--frames", FRAMES, "--quiet", "--out-dir", OUT]),
        )?;
    }
    // Section 2: the same with one band as tall as the image (a pool for the
    // whole frame).
    for s in OBJECTS {
        discard(
            hs().args(["sweep", "--scene", s])
                .args(SIZE)
                .args(["--frames", FRAMES, "--band", "240"])
                .args(["--policies", "fixed-merge,shared", "--splits", "1"])
                .args(["--name", &format!("{}-frame", tag(s))])
                .args(["--quiet", "--out-dir", OUT]),
        )?;
    }

    // Performance: one frame of the heaviest object, all policies and budgets;
    // the timing lines the sweep writes to its standard error are kept.
    let mut sweep = hs();
    sweep
        .args(["sweep", "--scene", "knot"])
        .args(SIZE)
        .args(BAND)
        .args(["--quiet", "--out-dir"])
        .arg(tmp);
    let timing = sweep_timing(&mut sweep)?;
    write(&format!("{OUT}/sweep-timing.txt"), &timing)?;

    // Section 3: the unlimited A-buffer against supersampled ground truth.
    let mut ssaa = String::from(
        "| scene | zbuffer vs ssaa 16x16 | unlimited 4x4 vs ssaa 16x16 | ssaa 4x4 vs ssaa 16x16 | unlimited 4x4 vs ssaa 4x4 | unlimited 8x8 vs ssaa 16x16 | ssaa 8x8 vs ssaa 16x16 | unlimited 8x8 vs ssaa 8x8 |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    for s in OBJECTS.into_iter().chain(["spheres", "teapot", LAYERS]) {
        let t = tag(s);
        let image = |suffix: &str| tmp.join(format!("{t}-{suffix}.png"));
        let render = |method: &[&str], out: PathBuf| {
            discard(
                hs().args(["render", "--scene", s])
                    .args(SIZE)
                    .args(method)
                    .arg("--out")
                    .arg(out),
            )
        };
        render(&["--method", "zbuffer"], image("z"))?;
        render(&["--method", "unlimited"], image("u4"))?;
        render(&["--method", "unlimited", "--grid", "8x8"], image("u8"))?;
        for n in ["4", "8", "16"] {
            render(&["--method", "ssaa", "--ssaa", n], image(&format!("s{n}")))?;
        }
        let mut row = format!("| {s} |");
        for (a, b) in [
            ("z", "s16"),
            ("u4", "s16"),
            ("s4", "s16"),
            ("u4", "s4"),
            ("u8", "s16"),
            ("s8", "s16"),
            ("u8", "s8"),
        ] {
            row.push_str(&format!(" {} |", nmse(hs(), &image(a), &image(b))?));
        }
        ssaa.push_str(&row);
        ssaa.push('\n');
    }
    write(&format!("{OUT}/ssaa.md"), ssaa.as_bytes())?;
    // Where the A-buffer's shading at pixel centers differs from shading per
    // sample.
    discard(
        hs().arg("compare")
            .arg(tmp.join("starfighter-u4.png"))
            .arg(tmp.join("starfighter-s4.png"))
            .args([
                "--diff",
                &format!("{OUT}/starfighter-unlimited-vs-ssaa4.png"),
            ]),
    )?;
    copy(
        &tmp.join("starfighter-s16.png"),
        &root.join(OUT).join("starfighter-ssaa16.png"),
    )?;

    // Section 1: where 3 fragments per pixel lose quality (shared, 1 main slot
    // and 2 pool addresses, a pool per band sized to the worst peak of the
    // sweep).
    for s in ["starfighter", "teapot:24"] {
        let t = tag(s);
        let peak = shared3_pool_peak(&format!("{OUT}/{t}-sweep.csv"))?;
        let shared3 = tmp.join(format!("{t}-shared3.png"));
        discard(
            hs().args(["render", "--scene", s])
                .args(SIZE)
                .args(["--method", "shared"])
                .args(BAND)
                .args(["--main", "1", "--extra", "2", "--pool", &peak, "--out"])
                .arg(&shared3),
        )?;
        discard(
            hs().arg("compare")
                .arg(&shared3)
                .arg(tmp.join(format!("{t}-u4.png")))
                .args(["--diff", &format!("{OUT}/{t}-shared3-vs-unlimited.png")])
                .args(["--diff-scale", "64"]),
        )?;
    }

    // Depth complexity: histograms, heat maps, memory.
    for s in OBJECTS.into_iter().chain([LAYERS]) {
        let stats = captured(
            hs().args(["stats", "--scene", s])
                .args(SIZE)
                .args(BAND)
                .args(["--pool", "1920", "--out-dir", OUT]),
        )?;
        write(&format!("{OUT}/{}-stats.txt", tag(s)), &stats)?;
    }

    // Bounded memory against unlimited over an 8-frame turntable: the default
    // M4 memory (band 8, pool 512) and the host defaults (band 16, pool 1,920).
    let m4 = captured(hs().args([
        "bounded",
        "--row-plot",
        &format!("{OUT}/bounded-rows-teapot.svg"),
    ]))?;
    write(&format!("{OUT}/bounded-m4.md"), &m4)?;
    let host = captured(hs().args(["bounded", "--band", "16", "--pool", "1920"]))?;
    write(&format!("{OUT}/bounded-host.md"), &host)?;
    // The fastest configuration within 112 KiB and within 96 KiB (the host's
    // times decide), all four in one file.
    let mut tune = Vec::new();
    for s in ["teapot", "spheres"] {
        for ram in ["112K", "96K"] {
            tune.extend(captured(
                hs().args(["tune", "--scene", s, "--ram", ram, "--show", "3"]),
            )?);
        }
    }
    write(&format!("{OUT}/tune.md"), &tune)?;

    // The dynamic mode: a turntable with per-frame statistics.
    let turntable = captured(
        hs().args(["render", "--scene", "starfighter"])
            .args(["--width", "160", "--height", "160"])
            .args(BAND)
            .args(["--pool", "1280", "--turntable", "--frames", "24"])
            .args(["--out", &format!("{OUT}/starfighter-turntable.gif")]),
    )?;
    write(&format!("{OUT}/starfighter-turntable.txt"), &turntable)?;

    println!("wrote {OUT}/");
    Ok(())
}

/// Runs `command` with its standard output discarded (the scripts'
/// `>/dev/null`); its standard error still reaches the terminal.
fn discard(command: &mut Command) -> Result<(), String> {
    status(command.stdout(Stdio::null()))
}

/// Runs `command` and returns its standard output (the scripts' `>file` and
/// `$(...)`); its standard error still reaches the terminal.
fn captured(command: &mut Command) -> Result<Vec<u8>, String> {
    println!("$ {}", describe(command));
    let out = command
        .stderr(Stdio::inherit())
        .output()
        .map_err(|e| format!("`{}` did not start: {e}", describe(command)))?;
    if out.status.success() {
        Ok(out.stdout)
    } else {
        Err(format!("`{}` failed ({})", describe(command), out.status))
    }
}

/// Runs the sweep `command` with its standard output discarded and returns the
/// lines of its standard error that start with `sweep:` (the script's
/// `2>&1 >/dev/null | grep '^sweep:'`); an error, as `grep`'s failure, when
/// there is none.
fn sweep_timing(command: &mut Command) -> Result<Vec<u8>, String> {
    println!("$ {}", describe(command));
    let out = command
        .stdout(Stdio::null())
        .output()
        .map_err(|e| format!("`{}` did not start: {e}", describe(command)))?;
    if !out.status.success() {
        return Err(format!(
            "`{}` failed ({}):\n{}",
            describe(command),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let mut lines = Vec::new();
    for line in out.stderr.split(|&b| b == b'\n') {
        if line.starts_with(b"sweep:") {
            lines.extend_from_slice(line);
            lines.push(b'\n');
        }
    }
    if lines.is_empty() {
        return Err(format!(
            "`{}` printed no `sweep:` line on its standard error",
            describe(command)
        ));
    }
    Ok(lines)
}

/// The NMSE of image `a` against image `b` from `host-sim compare` (`hs`), as
/// awk's `%.2e` prints it (`1.23e-04`).
fn nmse(mut hs: Command, a: &Path, b: &Path) -> Result<String, String> {
    let out = captured(hs.arg("compare").arg(a).arg(b))?;
    // Every line `NMSE <value>`, its second field (awk's `$2`), formatted.
    let text = String::from_utf8_lossy(&out);
    let mut nmse = String::new();
    for line in text.lines().filter(|l| l.starts_with("NMSE ")) {
        if let Some(value) = line.split_whitespace().nth(1) {
            // awk reads a field that is not a number as 0.
            nmse.push_str(&c_exponential(value.parse().unwrap_or(0.0)));
        }
    }
    Ok(nmse)
}

/// `x` as C's `printf("%.2e")`: two decimals and an exponent with its sign and
/// at least two digits (`1.23e-04`, `5.00e+00`).
fn c_exponential(x: f64) -> String {
    if x.is_nan() {
        return "nan".to_string();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    let rust = format!("{x:.2e}");
    let (mantissa, exponent) = rust.split_once('e').unwrap_or((&rust, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let sign = if exponent < 0 { '-' } else { '+' };
    format!("{mantissa}e{sign}{:02}", exponent.unsigned_abs())
}

/// A scene name usable in a file name: `:` becomes `-` (`teapot:24` ->
/// `teapot-24`).
fn tag(scene: &str) -> String {
    scene.replace(':', "-")
}

/// The worst pool peak (column 13) of `shared` at 3 fragments per pixel and 1
/// split (columns 7, 8 and 10) in the sweep CSV `csv` (relative to the
/// repository root), as the script's awk finds it.
fn shared3_pool_peak(csv: &str) -> Result<String, String> {
    let path = repo_root().join(csv);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    // awk compares the fields numerically when they look like numbers.
    let is = |field: &str, n: f64| field.trim().parse::<f64>().is_ok_and(|v| v == n);
    let peaks: Vec<&str> = text
        .lines()
        .map(|line| line.split(',').collect::<Vec<_>>())
        .filter(|f| f.len() >= 13 && f[6] == "shared" && is(f[7], 3.0) && is(f[9], 1.0))
        .map(|f| f[12])
        .collect();
    match peaks[..] {
        [peak] => Ok(peak.to_string()),
        _ => Err(format!(
            "{csv}: {} rows of shared at 3 fragments per pixel and 1 split, not one",
            peaks.len()
        )),
    }
}

/// Writes `contents` to `file` (relative to the repository root).
fn write(file: &str, contents: &[u8]) -> Result<(), String> {
    let path = repo_root().join(file);
    std::fs::write(&path, contents).map_err(|e| format!("{}: {e}", path.display()))
}

/// Copies file `from` to `to`.
fn copy(from: &Path, to: &Path) -> Result<(), String> {
    std::fs::copy(from, to)
        .map(drop)
        .map_err(|e| format!("cp {} {}: {e}", from.display(), to.display()))
}
