//! Bakes a scene and the buffer parameters into the firmware binaries.
//!
//! Only firmware features do anything here; library builds (host tests, plain
//! bare-metal builds) skip it. Inputs, all optional:
//!
//! | variable | meaning | default |
//! |---|---|---|
//! | `FIRMWARE_SCENE` | built-in scene name or a scene file (relative to the repository root) | M4: `teapot`, OLED: `teapot:4` |
//! | `FIRMWARE_WIDTH`, `FIRMWARE_HEIGHT` | image size (overrides the scene's and the board's) | M4: 240 x 240, OLED: 128 x 64 |
//! | `FIRMWARE_FRAMES` | turntable frames, evenly spaced over 360 degrees | 4 |
//! | `FIRMWARE_METHOD` | `split-bands`, `shared`, `fixed-discard`, `fixed-merge`, `merge-closest`, `unlimited`, `zbuffer` | `split-bands` |
//! | `FIRMWARE_GRID` | `4x4`, `8x4`, `8x8` | `4x4` |
//! | `FIRMWARE_BAND` | band height in rows | 6, `zbuffer` 24 (`mcu_abuffer::memory::defaults`) |
//! | `FIRMWARE_MAIN`, `FIRMWARE_EXTRA`, `FIRMWARE_POOL` | `N_main`, `N_extra`, `N_pool` | 1, 2, 1152 (the same) |
//! | `FIRMWARE_FIXED` | `N_fixed` for the fixed methods | 3 (the same) |
//! | `FIRMWARE_STACK_RESERVE` | bytes kept free for the stack | 10240 (the same) |
//!
//! Parameters that do not fit the board's RAM (or a mesh that does not fit its flash)
//! stop the build with a message naming them and the overshoot.

use abuffer_scenes::bake::bake_scene;
use abuffer_scenes::builtins::builtin_scene;
use abuffer_scenes::fixed_bits::{check_convertible, coord_bits};
use abuffer_scenes::scene_desc::SceneDesc;
use abuffer_scenes::scene_file::load_scene_file;
use mcu_abuffer::memory::{bytes, defaults};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A firmware target: its feature, memory layout file and memory sizes.
struct Board {
    feature: &'static str,
    layout: &'static str,
    flash: usize,
    ram: usize,
    default_scene: &'static str,
    width: u32,
    height: u32,
    /// Bytes of one color of the z-buffer: its pixels are those of the
    /// build's line sink (`ZBufferPixel` in src/common.rs).
    zbuffer_pixel_bytes: usize,
}

const BOARDS: &[Board] = &[
    Board {
        feature: "M4",
        layout: "memory/mps2-an386.x",
        flash: 512 * 1024,
        ram: 128 * 1024,
        default_scene: "teapot",
        width: 240,
        height: 240,
        // `PackedRgb888`: the PPM file's pixels.
        zbuffer_pixel_bytes: 3,
    },
    Board {
        feature: "OLED",
        layout: "memory/lm3s6965.x",
        flash: 256 * 1024,
        ram: 64 * 1024,
        default_scene: "teapot:4",
        width: 128,
        height: 64,
        // `Gray4`: the OLED's gray levels.
        zbuffer_pixel_bytes: 1,
    },
];

/// Flash set aside for code and constants besides the meshes.
const CODE_RESERVE: usize = 96 * 1024;

fn env(name: &str) -> Option<String> {
    println!("cargo:rerun-if-env-changed={name}");
    std::env::var(name).ok().filter(|v| !v.is_empty())
}

fn env_num(name: &str, default: usize) -> usize {
    match env(name) {
        None => default,
        Some(v) => v
            .parse()
            .unwrap_or_else(|_| fail(&format!("{name}={v} is not a whole number"))),
    }
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    panic!("{message}");
}

fn load(spec: &str, root: &Path, board: &Board) -> SceneDesc {
    let path = if Path::new(spec).is_absolute() {
        PathBuf::from(spec)
    } else {
        root.join(spec)
    };
    if spec.ends_with(".toml") || path.is_file() {
        println!("cargo:rerun-if-changed={}", path.display());
        load_scene_file(&path).unwrap_or_else(|e| fail(&format!("FIRMWARE_SCENE: {e}")))
    } else {
        builtin_scene(spec, board.width, board.height).unwrap_or_else(|| {
            fail(&format!(
                "FIRMWARE_SCENE: '{spec}' is neither a scene file nor a built-in scene"
            ))
        })
    }
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory");
    let mut boards = BOARDS
        .iter()
        .filter(|b| std::env::var(format!("CARGO_FEATURE_{}", b.feature)).is_ok());
    let Some(board) = boards.next() else {
        fail("enable one board feature: m4 or oled");
    };
    if boards.next().is_some() {
        fail("enable only one board feature (m4 or oled): use --no-default-features --features oled for the OLED build");
    }
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    // The repository root: scene paths are relative to it.
    let root = manifest
        .join("../..")
        .canonicalize()
        .unwrap_or(manifest.clone());

    // Memory layout and link scripts for the binaries.
    std::fs::copy(manifest.join(board.layout), out.join("memory.x")).expect("copy memory layout");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");

    let spec = env("FIRMWARE_SCENE").unwrap_or_else(|| board.default_scene.into());
    let mut desc = load(&spec, &root, board);
    desc.width = board.width;
    desc.height = board.height;
    if let Some(w) = env("FIRMWARE_WIDTH") {
        desc.width = w
            .parse()
            .unwrap_or_else(|_| fail("FIRMWARE_WIDTH must be a number"));
    }
    if let Some(h) = env("FIRMWARE_HEIGHT") {
        desc.height = h
            .parse()
            .unwrap_or_else(|_| fail("FIRMWARE_HEIGHT must be a number"));
    }
    check_convertible(&desc).unwrap_or_else(|e| fail(&format!("FIRMWARE_SCENE {spec}: {e}")));
    let frames = env_num("FIRMWARE_FRAMES", 4).max(1);
    let method = env("FIRMWARE_METHOD").unwrap_or_else(|| "split-bands".into());
    let grid = env("FIRMWARE_GRID").unwrap_or_else(|| "4x4".into());
    let default_band = defaults::band_rows(method == "zbuffer") as usize;
    let band = env_num("FIRMWARE_BAND", default_band).clamp(1, desc.height as usize);
    let fixed = env_num("FIRMWARE_FIXED", defaults::FIXED_SLOTS as usize);
    let sized = || {
        (
            env_num("FIRMWARE_MAIN", defaults::MAIN_SLOTS as usize),
            env_num("FIRMWARE_EXTRA", defaults::EXTRA_ADDRESSES as usize),
            env_num("FIRMWARE_POOL", defaults::POOL_SLOTS),
        )
    };
    let (mask_type, mask_bytes, samples) = match grid.as_str() {
        "4x4" => ("Mask4x4", 2, 16),
        "8x4" => ("Mask8x4", 4, 32),
        "8x8" => ("Mask8x8", 8, 64),
        other => fail(&format!("FIRMWARE_GRID={other}: use 4x4, 8x4 or 8x8")),
    };
    let (policy, main, extra, pool) = match method.as_str() {
        "shared" => {
            let (main, extra, pool) = sized();
            ("MergeFarthest", main, extra, pool)
        }
        "merge-closest" => {
            let (main, extra, pool) = sized();
            ("MergeClosest", main, extra, pool)
        }
        "split-bands" => {
            let (main, extra, pool) = sized();
            ("SplitBands", main, extra, pool)
        }
        "fixed-discard" => ("Discard", fixed, 0, 0),
        "fixed-merge" => ("MergeFarthest", fixed, 0, 0),
        "unlimited" => ("MergeFarthest", 1, samples - 1, desc.width as usize * band * (samples - 1)),
        "zbuffer" => ("MergeFarthest", 0, 0, 0),
        other => fail(&format!("FIRMWARE_METHOD={other}: use split-bands, shared, merge-closest, fixed-discard, fixed-merge, unlimited or zbuffer")),
    };
    if method != "zbuffer" && (main == 0 || main + extra > 255) {
        fail(&format!("FIRMWARE_MAIN={main} FIRMWARE_EXTRA={extra}: need 1 <= N_main and N_main + N_extra <= 255"));
    }
    if pool > 65535 {
        fail(&format!(
            "FIRMWARE_POOL={pool}: a pool address is 16 bits, so at most 65535 slots"
        ));
    }
    let stack_reserve = env_num("FIRMWARE_STACK_RESERVE", defaults::STACK_RESERVE_BYTES);

    // The scene as Rust statics, and what they will take.
    let baked = bake_scene(&desc, &format!("FIRMWARE_SCENE={spec}"))
        .unwrap_or_else(|e| fail(&format!("FIRMWARE_SCENE {spec}: {e}")));
    let (vertices, triangles) = (baked.vertices, baked.triangles);
    let (w, h) = (desc.width as usize, desc.height as usize);
    // The library's own byte counts of the statics in src/common.rs.
    let buffer_bytes = if method == "zbuffer" {
        bytes::zbuffer_memory(w, band, board.zbuffer_pixel_bytes)
    } else {
        bytes::fragment_memory(mask_bytes, w, band, main, extra, pool)
    };
    let carried = env_num("FIRMWARE_CARRIED", defaults::CARRIED_COLORS);
    let workspace_bytes =
        bytes::workspace_memory(h, desc.objects.len(), vertices, triangles, carried);
    let ram_needed = buffer_bytes + workspace_bytes + stack_reserve;
    if ram_needed > board.ram {
        fail(&format!(
            "{w}x{h}, band {band}, {method} {grid} (main {main}, extra {extra}, pool {pool}) with {vertices} vertices and {triangles} triangles \
             needs {ram_needed} bytes of RAM ({buffer_bytes} fragment buffer + {workspace_bytes} frame workspace + {stack_reserve} stack reserve): \
             does not fit {} bytes by {} bytes",
            board.ram,
            ram_needed - board.ram
        ));
    }
    let mesh_bytes = baked.mesh_bytes;
    if mesh_bytes + CODE_RESERVE > board.flash {
        fail(&format!(
            "FIRMWARE_SCENE {spec}: meshes take {mesh_bytes} bytes; with {CODE_RESERVE} bytes for code they do not fit {} bytes of flash by {} bytes",
            board.flash,
            mesh_bytes + CODE_RESERVE - board.flash
        ));
    }
    let mut s = baked.source;
    // Turntable angles: frame i of K at 360 i / K degrees, converted like host-sim's --angle.
    let angles: Vec<String> = (0..frames)
        .map(|i| coord_bits(360.0 * i as f32 / frames as f32).to_string())
        .collect();
    writeln!(s, "/// Turntable angle of each frame, Q16.16 degrees.\npub static FRAME_ANGLES: [i32; {frames}] = [{}];", angles.join(", ")).unwrap();
    std::fs::write(out.join("scene_data.rs"), s).expect("write scene_data.rs");

    let method_const = match method.as_str() {
        "zbuffer" => "Method::ZBuffer",
        _ => "Method::ABuffer",
    };
    let config = format!(
        "// Generated by build.rs.\n\
         /// Scene name as given.\npub const SCENE_NAME: &str = {spec:?};\n\
         /// Method name as given.\npub const METHOD_NAME: &str = {method:?};\n\
         /// Grid name.\npub const GRID_NAME: &str = {grid:?};\n\
         /// Coverage mask of this build.\npub type Mask = mcu_abuffer::coverage::{mask_type};\n\
         /// Which pixel memory this build uses.\npub const METHOD: Method = {method_const};\n\
         /// Overflow policy of the A-buffer.\npub const POLICY: OverflowPolicy = OverflowPolicy::{policy};\n\
         /// Image size.\npub const WIDTH: usize = {w};\npub const HEIGHT: usize = {h};\n\
         /// Band height.\npub const BAND: usize = {band};\n\
         /// Fragment slots and pool addresses per pixel, pool slots.\npub const MAIN: usize = {main};\npub const EXTRA: usize = {extra};\npub const POOL: usize = {pool};\n\
         /// Carried-colors entries.\npub const CARRIED: usize = {carried};\n\
         /// Scene size.\npub const VERTICES: usize = {vertices};\npub const TRIANGLES: usize = {triangles};\npub const OBJECTS_LEN: usize = {objects};\n\
         /// Turntable frames.\npub const FRAMES: usize = {frames};\n\
         /// Bytes the build script counted for the band buffer and the workspace (checked against the types).\npub const BUFFER_BYTES: usize = {buffer_bytes};\npub const WORKSPACE_BYTES: usize = {workspace_bytes};\n",
        objects = desc.objects.len(),
    );
    std::fs::write(out.join("config.rs"), config).expect("write config.rs");
}
