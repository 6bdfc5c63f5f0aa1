//! Tells the library what multiplies its target has:
//! - `arm_long_multiply`: the Armv7-M long multiplies (`smull`, `smlal`).
//!   Cortex-M3, M4, M7 and the Armv8-M mainline cores have them, Armv6-M
//!   (Cortex-M0, M0+) does not. With them, the quadratic fit issues its
//!   32 x 32 -> 64-bit products in source order
//!   ([`fixed_point::wide_mul`](src/fixed_point.rs)).
//! - `arm_dual_multiply`: the DSP extension's dual 16-bit multiply-add
//!   (`smuad`) of Armv7E-M (Cortex-M4, M7). With it, a coverage mask's
//!   thresholds take one multiplication each
//!   ([`coverage`](src/coverage.rs), `Edge4x4::mask_short`).

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo::rustc-check-cfg=cfg(arm_long_multiply)");
    println!("cargo::rustc-check-cfg=cfg(arm_dual_multiply)");
    let target = std::env::var("TARGET").unwrap_or_default();
    let long_multiply = ["thumbv7m", "thumbv7em", "thumbv8m.main"]
        .iter()
        .any(|arch| target.starts_with(arch));
    if long_multiply {
        println!("cargo::rustc-cfg=arm_long_multiply");
    }
    if target.starts_with("thumbv7em") {
        println!("cargo::rustc-cfg=arm_dual_multiply");
    }
}
