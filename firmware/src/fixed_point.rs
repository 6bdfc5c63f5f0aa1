//! Fixed-point formats of the pipeline and the integer math they need.
//!
//! Every quantity after scene loading is an integer with a stated format and a
//! stated range, and each range keeps the arithmetic that uses it inside its type.
//! The table follows a vertex from the scene to the screen; each type's own
//! documentation repeats its line with the detail, and `tests/tests/ranges.rs`
//! drives every quantity to its limits with overflow checks on.
//!
//! | quantity | type, format | range | why nothing overflows |
//! |---|---|---|---|
//! | model, world and camera coordinates, angles, scales | [`Coord`] (Q16.16) | ±32768 | the type; host scenes are converted with model coordinates within ±16384 and other values within ±32767, NaN refused |
//! | unit vectors (normals, light) | `i32` / `I2F14` (Q2.14) | components ±2^14, length 1 ± 1/128 | [`crate::scene::Scene::validate`] refuses other normals; the light is normalized per frame |
//! | composed model-view-projection | `i128`, Q32 | below 2^100 | products of Q30 rotations with Q16.16 values |
//! | per-object clip transform | [`crate::geometry::ClipTransform`]: `i32` entries, `i64` offsets, one scale per object | entries at most 2^27, offsets at most 2^59 | the scale is chosen from the largest entry and offset |
//! | clip-space `X, Y, Zs, w` of a vertex | `i64` | below 2^61 | `3 * 2^27 * 2^31 + 2^59` |
//! | clip tests and the perspective divide | `i64` | at most 2^38 after a shift per vertex; `4096 w` below 2^50 | window coordinates are ratios, a common shift of a vertex changes none |
//! | clipping a triangle | `i64` components, `i128` distances | at most 2^38 after a shift common to the triangle; distances below 2^51, products below 2^91 | [`crate::clip::clip_triangle`] |
//! | window coordinates | [`SubPixel`] (Q27.4, 1/16 pixel) | ±2^16 (±[`GUARD_BAND_PX`] px) | clipped to the guard band, clamped by the divide and again by setup |
//! | window depth | `u32`, 24 fraction bits, 0 = near | `0 ..= DEPTH_MAX` | clamped by the divide |
//! | vertex colors | [`crate::lighting::ColorQ8`] (Q8) | `0 ..= 255 * 256` | lighting clamps; clipping interpolates between two such |
//! | edge coefficients `A`, `B` | `i64`, 1/16 pixel | at most 2^17 | differences of two window coordinates |
//! | edge values at pixels and samples | `i64`, or `i32` when all of a triangle's fit | below 2^36 on screen; within a pixel's margin (below 2^22) per sample | `A x + B y + C` over the guard band; the rasterizer takes `i32` only after bounding every value it will step to |
//! | depth plane | `i64`, depth x 2^16 per pixel | gradients ±2^40 (saturated), values below 2^59 | gradient times a guard-band distance plus `2^44` |
//! | fragment depth gradients | `i32` (24 bits stored) | ±[`crate::fragment::GRADIENT_LIMIT`] | saturated by setup, clamped when packed |
//! | depth at a sample, x 16 | `i32` | below 2^29 | `16 * 2^24 + 2 * 7 * 2^23` |
//! | visibility difference plane | `i32` | below 2^30 | the difference of two of those |
//! | Gouraud color planes | `i64`, Q8 x 2^16 | gradients below 2^46, values at on-screen pixels below 2^62.6 | see [`crate::setup::Plane`] |
//! | quadratic and Phong planes | `i64` | see [`crate::shading`] | the fit falls back to Gouraud planes where its bounds would not hold |
//! | lighting | `i32`, Q2.14 | coefficients below 8, dot products at most 1 | products below 2^31 |
//! | merge | `u32` | products below 2^30 | depths differ by less than 2^24, popcounts at most 64 |
//! | resolve | `u32` | sums below 255 * 64 per channel | at most 64 samples of 8 bits |
//! | fragments per pixel, pool slots | `u8` counts, pool addresses | at most 255, at most the address type's pool | checked when a [`crate::fragment_buffer::FragmentBuffer`] is built |
//!
//! Window coordinates are snapped to 1/16 pixel. Sample offsets of every supported
//! coverage grid (4x4, 8x4, 8x8) are odd multiples of 1/16 or 1/8 pixel, so every
//! sample position is exact and edge functions at samples are exact integers.

/// Model and world coordinates: Q16.16, range ±32768 with steps of 2^-16.
///
/// Also the camera, the light's coefficients, placements, angles and the
/// turntable. Every use widens first: positions are multiplied by 32-bit matrix
/// entries in `i64` ([`crate::geometry::ObjectTransform::to_clip`]), everything
/// else is composed in `i128`. The host's conversion keeps model coordinates
/// within ±16384 and refuses NaN and values beyond ±32767; the device API may
/// use the whole range.
pub type Coord = fixed::types::I16F16;

/// Window coordinates in 1/16 pixel (Q27.4).
///
/// Range: ±2^16, that is ±[`GUARD_BAND_PX`] pixels. Vertices outside the guard
/// band are clipped in clip space, the perspective divide clamps its result to
/// the band, and triangle setup clamps again, so every product of two window
/// coordinates (edge functions, areas) is below 2^35.
pub type SubPixel = i32;

/// Fraction bits of [`SubPixel`].
pub const SUBPIXEL_BITS: u32 = 4;
/// One pixel in [`SubPixel`] units.
pub const SUBPIXEL_ONE: i32 = 1 << SUBPIXEL_BITS;

/// Window coordinates are kept within `±GUARD_BAND_PX` pixels by clipping, which
/// bounds edge functions (below 2^36) and depth-plane numerators (below 2^43).
pub const GUARD_BAND_PX: i32 = 4096;

/// Fraction bits of window depth.
pub const DEPTH_BITS: u32 = 24;
/// The largest window depth (the far plane). Depths are `0 ..= DEPTH_MAX` from
/// the perspective divide on (it clamps), so differences of two fit 25 bits and
/// a depth times 16 (sample depths) fits 28.
pub const DEPTH_MAX: u32 = (1 << DEPTH_BITS) - 1;

/// Fraction bits of unit vectors (normals, light direction).
pub const UNIT_BITS: u32 = 14;
/// 1.0 in unit-vector format. Unit vectors have components within
/// `±UNIT_ONE` (a little more after rounding), so a dot product of two is a sum
/// of three products below 2^29 and fits `i32`.
pub const UNIT_ONE: i32 = 1 << UNIT_BITS;

/// Integer square root: the largest `r` with `r * r <= n`.
pub const fn isqrt_u64(n: u64) -> u64 {
    if n < 2 {
        return n;
    }
    // Bit-by-bit method: deterministic, no division, at most 32 iterations.
    let mut rem = n;
    let mut root: u64 = 0;
    let mut bit: u64 = 1 << 62;
    while bit > rem {
        bit >>= 2;
    }
    while bit != 0 {
        if rem >= root + bit {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// Q30 fixed-point one.
const Q30: i64 = 1 << 30;

/// Sine and cosine of `x` radians in Q30, for `0 <= x <= pi/4` (x in Q30).
fn sin_cos_octant(x: i64) -> (i64, i64) {
    // Taylor series to the x^11 / x^12 terms: error below 1e-10 on [0, pi/4].
    let x2 = (x * x) >> 30;
    // sin = x (1 - x2/6 (1 - x2/20 (1 - x2/42 (1 - x2/72 (1 - x2/110)))))
    let mut s = Q30 - x2 / 110;
    s = Q30 - ((x2 * s) >> 30) / 72;
    s = Q30 - ((x2 * s) >> 30) / 42;
    s = Q30 - ((x2 * s) >> 30) / 20;
    s = Q30 - ((x2 * s) >> 30) / 6;
    let sin = (x * s) >> 30;
    // cos = 1 - x2/2 (1 - x2/12 (1 - x2/30 (1 - x2/56 (1 - x2/90 (1 - x2/132)))))
    let mut c = Q30 - x2 / 132;
    c = Q30 - ((x2 * c) >> 30) / 90;
    c = Q30 - ((x2 * c) >> 30) / 56;
    c = Q30 - ((x2 * c) >> 30) / 30;
    c = Q30 - ((x2 * c) >> 30) / 12;
    let cos = Q30 - ((x2 * c) >> 30) / 2;
    (sin, cos)
}

/// Sine and cosine of an angle in degrees, as Q30 (`1 << 30` is 1.0).
///
/// Integer-only and deterministic: the same bits on every target.
pub fn sin_cos_deg(deg: Coord) -> (i32, i32) {
    // Reduce to [0, 360) degrees in Q16, then to an octant and an offset within it.
    let full = 360i64 << 16;
    let d = (deg.to_bits() as i64).rem_euclid(full);
    let eighth = 45i64 << 16;
    let octant = d / eighth;
    let rem = d - octant * eighth;
    // Offset in radians, Q30: rem (Q16 degrees) * pi/180.
    // pi/180 in Q46, rounded.
    const PI_OVER_180_Q46: i64 = 1_228_166_276_394;
    // deg_q16 < 45 * 2^16, so the product stays below 2^62.
    let to_rad = |deg_q16: i64| (deg_q16 * PI_OVER_180_Q46 + (1 << 31)) >> 32;
    let (s, c) = match octant {
        0 => sin_cos_octant(to_rad(rem)),
        1 => {
            let (s, c) = sin_cos_octant(to_rad(eighth - rem));
            (c, s)
        }
        2 => {
            let (s, c) = sin_cos_octant(to_rad(rem));
            (c, -s)
        }
        3 => {
            let (s, c) = sin_cos_octant(to_rad(eighth - rem));
            (s, -c)
        }
        4 => {
            let (s, c) = sin_cos_octant(to_rad(rem));
            (-s, -c)
        }
        5 => {
            let (s, c) = sin_cos_octant(to_rad(eighth - rem));
            (-c, -s)
        }
        6 => {
            let (s, c) = sin_cos_octant(to_rad(rem));
            (-c, s)
        }
        _ => {
            let (s, c) = sin_cos_octant(to_rad(eighth - rem));
            (-s, c)
        }
    };
    (s.clamp(-Q30, Q30) as i32, c.clamp(-Q30, Q30) as i32)
}

/// The reciprocal of a positive integer, so that divisions by it become
/// multiplications: one per triangle (twice its area) or per vertex (its `w`)
/// replaces the 64-bit software divisions a Cortex-M would otherwise run for
/// every plane gradient and window coordinate.
///
/// `d` is normalized to `[2^31, 2^32)` (its low bits dropped when it is longer),
/// one 32-bit hardware division gives 16 bits of `2^63 / d`, and one Newton step
/// brings the mantissa to about 30 correct bits. [`Reciprocal::mul_div`] then
/// computes `n 2^extra / d` to within a relative error below `2^-29` (plus one
/// unit), deterministically: the same bits on every target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reciprocal {
    /// About `2^63 / d_n`, in `(2^31, 2^32)`, for `d` normalized to `d_n`.
    mantissa: u32,
    /// `n / d` is about `n * mantissa >> shift`.
    shift: u32,
}

/// About `2^63 / d` for `d` in `[2^31, 2^32)`, within a few units.
#[inline]
fn reciprocal_mantissa(d: u32) -> u32 {
    // 16-bit estimate from the hardware divider: 2^31 / (d >> 16) ~ 2^47 / d.
    let estimate = ((1u32 << 31) / (d >> 16)) as u64;
    let r = estimate << 16;
    // One Newton step: r (2 - d r / 2^63), with the error term scaled to fit.
    let error = ((d as u64).wrapping_mul(r)).wrapping_sub(1 << 63) as i64;
    let correction = ((r as i64) * (error >> 20)) >> 43;
    (r as i64 - correction).clamp(1 << 31, u32::MAX as i64) as u32
}

/// `v >> s` for a shift below 32, word by word: the compiler's 64-bit
/// shift by a variable amount also handles 32 to 63, with more
/// instructions.
#[inline(always)]
fn shift_below_32(v: i64, s: u32) -> i64 {
    debug_assert!(s < 32);
    let (low, high) = (v as u32, (v >> 32) as i32);
    let low = (low >> (s & 31)) | ((high as u32) << 1 << (31 - (s & 31)));
    (((high >> (s & 31)) as i64) << 32) | low as i64
}

impl Reciprocal {
    /// The reciprocal of `d`, `1 <= d < 2^62`.
    #[inline]
    pub fn new(d: u64) -> Self {
        let d = d.clamp(1, (1 << 62) - 1);
        // Normalize to [2^31, 2^32): d_n = d 2^k.
        let k = d.leading_zeros() as i32 - 32;
        let normalized = if k >= 0 { d << k } else { d >> -k } as u32;
        Self {
            mantissa: reciprocal_mantissa(normalized),
            // n / d = n 2^k / d_n = n mantissa 2^(k - 63).
            shift: (63 - k) as u32,
        }
    }

    /// `n 2^extra / d`, rounded down (within one unit and the relative error
    /// above), for `|n| < 2^62`; the result (times two, for
    /// [`Reciprocal::mul_div_round`]) must fit `i64`.
    // Always inlined: the compiler moved it out of color setup once the fit
    // took setup's reciprocal (see `shading::walks_in_i32`).
    #[inline(always)]
    pub fn mul_div(self, n: i64, extra: u32) -> i64 {
        if let Some(shift) = self.short_shift(n.unsigned_abs(), extra) {
            return (n * self.mantissa as i64) >> shift;
        }
        if self.shift >= extra + 32 {
            return self.mul_div_by_large(n, extra);
        }
        self.mul_div_wide(n, extra)
    }

    /// [`Reciprocal::mul_div`] for a divisor large against `2^extra`
    /// (`shift >= extra + 32`, a vertex's `w`): the quotient is below the
    /// product's high word, so the halves need no room made for `2^extra`
    /// first (the same bits again).
    #[inline(always)]
    fn mul_div_by_large(self, n: i64, extra: u32) -> i64 {
        let high = (n >> 32) * self.mantissa as i64;
        let low = ((n as u32 as u64 * self.mantissa as u64) >> 32) as i64;
        (high + low) >> (self.shift - extra - 32)
    }

    /// [`Reciprocal::mul_div`] of each of `numerators` (the same bits), with
    /// the test for short numerators and the shift made once for all: the
    /// gradients of one plane, or of a triangle's three color planes.
    #[inline]
    pub fn mul_div_each<const N: usize>(self, numerators: [i64; N], extra: u32) -> [i64; N] {
        let magnitudes = numerators.iter().fold(0, |m, n| m | n.unsigned_abs());
        match self.short_shift(magnitudes, extra) {
            Some(shift) => self.short_quotients(numerators, shift),
            None => numerators.map(|n| self.mul_div(n, extra)),
        }
    }

    /// [`Reciprocal::mul_div_each`] of numerators that fit a word (none
    /// `i32::MIN`): the same bits, with no test of their size.
    #[inline]
    pub fn mul_div_each_word<const N: usize>(self, numerators: [i32; N], extra: u32) -> [i64; N] {
        let numerators = numerators.map(i64::from);
        match self.short_shift((1 << 31) - 1, extra) {
            Some(shift) => self.short_quotients(numerators, shift),
            None => numerators.map(|n| self.mul_div(n, extra)),
        }
    }

    /// The quotients of numerators below 2^31 in magnitude by the short
    /// path's `shift` ([`Reciprocal::short_shift`]): each `n mantissa`, one
    /// 32 x 32-bit product, shifted.
    #[inline(always)]
    fn short_quotients<const N: usize>(self, numerators: [i64; N], shift: u32) -> [i64; N] {
        let mantissa = self.mantissa as i64;
        if shift >= 32 {
            // The product's high word, shifted on in 32 bits.
            numerators.map(|n| (((n * mantissa) >> 32) as i32 >> (shift - 32)) as i64)
        } else {
            numerators.map(|n| shift_below_32(n * mantissa, shift))
        }
    }

    /// The shift that takes `n mantissa` to the quotient, for numerators of
    /// at most `magnitudes` (their bits or-ed) that the short path takes.
    /// The quotient is `floor(n mantissa 2^extra / 2^shift)` whenever the
    /// whole `2^extra` fits into `n` below (no bit of `n` dropped). Below
    /// 2^31 the product `n mantissa` fits `i64`, so one multiplication and
    /// this shift give the same bits as the two partial products (the
    /// numerators of most setups are this small). `None` otherwise.
    #[inline]
    fn short_shift(self, magnitudes: u64, extra: u32) -> Option<u32> {
        // Below 2^31 the leading zeros are at least 33: with `extra <= 31`
        // (every constant scale of setup) the count need not be taken.
        let fits = extra <= 31 || magnitudes.leading_zeros() >= extra + 2;
        (magnitudes < 1 << 31 && fits && self.shift >= extra).then(|| (self.shift - extra).min(63))
    }

    /// [`Reciprocal::mul_div`] for any numerator: the product in two halves.
    #[inline]
    fn mul_div_wide(self, n: i64, extra: u32) -> i64 {
        // Move as much of 2^extra into n as fits, so the product keeps its bits.
        let headroom = (n.unsigned_abs().leading_zeros() as i32 - 2).max(0) as u32;
        let early = extra.min(headroom);
        let n = n << early;
        // (n mantissa) >> 32 exactly rounded down, from two 32 x 32 products.
        let high = (n >> 32) * self.mantissa as i64;
        let low = ((n as u32 as u64 * self.mantissa as u64) >> 32) as i64;
        let product = high + low;
        let shift = self.shift as i32 - 32 - (extra - early) as i32;
        if shift >= 0 {
            product >> shift
        } else {
            product << -shift
        }
    }

    /// `n 2^extra / d` rounded to nearest (within the same error).
    #[inline]
    pub fn mul_div_round(self, n: i64, extra: u32) -> i64 {
        (self.mul_div(n, extra + 1) + 1) >> 1
    }

    /// [`Reciprocal::mul_div`] with the test for a divisor large against
    /// `2^extra` made before the test for a short numerator: the same bits,
    /// for numerators that are seldom short (a vertex's window `x` and `y`,
    /// whose `w` is large). Both paths give `floor(n mantissa 2^extra /
    /// 2^shift)` exactly (shifts of exact products, and floors of floors by
    /// powers of two), so the order does not change the quotient.
    #[inline]
    pub fn mul_div_large_divisor(self, n: i64, extra: u32) -> i64 {
        if self.shift >= extra + 32 {
            self.mul_div_by_large(n, extra)
        } else {
            self.mul_div(n, extra)
        }
    }

    /// `n / d`, as [`Reciprocal::mul_div`] with no extra factor.
    #[inline]
    pub fn divide(self, n: i64) -> i64 {
        self.mul_div(n, 0)
    }
}

/// `x y`, one 32 x 32 -> 64-bit multiplication.
///
/// On Armv7-M and Armv8-M mainline (the build script's `arm_long_multiply`)
/// this is one `smull` written out, and [`wide_mul_add`] one `smlal`: the
/// compiler keeps such instructions in the order of the source, so a
/// computation that uses each product soon after making it keeps few values
/// live. Left to itself, the compiler hoisted the quadratic fit's eighteen
/// products to its start and spilled them (its narrow case took 910
/// instructions instead of about 740). Elsewhere plain multiplication: the
/// same bits.
#[inline(always)]
pub fn wide_mul(x: i32, y: i32) -> i64 {
    #[cfg(arm_long_multiply)]
    {
        let (low, high): (u32, i32);
        // SAFETY: register-only arithmetic, no memory, stack or flags.
        unsafe {
            core::arch::asm!(
                "smull {low}, {high}, {x}, {y}",
                low = lateout(reg) low,
                high = lateout(reg) high,
                x = in(reg) x,
                y = in(reg) y,
                options(nomem, nostack, preserves_flags)
            );
        }
        ((high as i64) << 32) | low as i64
    }
    #[cfg(not(arm_long_multiply))]
    {
        x as i64 * y as i64
    }
}

/// `acc + x y`, one 32 x 32 -> 64-bit multiply-accumulate (`smlal` on
/// Armv7-M, see [`wide_mul`]). The sum must fit `i64`.
#[inline(always)]
pub fn wide_mul_add(acc: i64, x: i32, y: i32) -> i64 {
    #[cfg(arm_long_multiply)]
    {
        let (mut low, mut high) = (acc as u32, (acc >> 32) as i32);
        // SAFETY: register-only arithmetic, no memory, stack or flags.
        unsafe {
            core::arch::asm!(
                "smlal {low}, {high}, {x}, {y}",
                low = inout(reg) low,
                high = inout(reg) high,
                x = in(reg) x,
                y = in(reg) y,
                options(nomem, nostack, preserves_flags)
            );
        }
        ((high as i64) << 32) | low as i64
    }
    #[cfg(not(arm_long_multiply))]
    {
        acc + x as i64 * y as i64
    }
}

/// `acc + n d` for a count `n` (a depth plane's value `n` pixels on from
/// `acc`), wrapping; the caller knows the sum fits. On Armv7-M (the build
/// script's `arm_long_multiply`) one `umlal` and one `mla` written out: the
/// unsigned product of `n` and `d`'s low word added into `acc`, then `n`
/// times `d`'s high word into the high word. Left to the compiler (a
/// 64-bit product, then a 64-bit sum), the pixel walks of the teapot's
/// antialiased frame took 0.14 M instructions more; the z-buffer's runs,
/// whose loops differ, do not gain from it and keep the plain sum.
#[inline(always)]
pub fn count_mul_add(acc: i64, n: u32, d: i64) -> i64 {
    #[cfg(arm_long_multiply)]
    {
        let (mut low, mut high) = (acc as u32, (acc >> 32) as u32);
        // SAFETY: register-only arithmetic, no memory, stack or flags.
        unsafe {
            core::arch::asm!(
                "umlal {low}, {high}, {n}, {dl}",
                "mla {high}, {n}, {dh}, {high}",
                low = inout(reg) low,
                high = inout(reg) high,
                n = in(reg) n,
                dl = in(reg) d as u32,
                dh = in(reg) (d >> 32) as u32,
                options(pure, nomem, nostack, preserves_flags)
            );
        }
        ((high as u64) << 32 | low as u64) as i64
    }
    #[cfg(not(arm_long_multiply))]
    {
        acc.wrapping_add((n as i64).wrapping_mul(d))
    }
}

/// `acc + n d` in a word, wrapping, for a count `n` (an edge value `n`
/// pixels on from `acc`); the caller knows the sum fits. On Armv7-M (the
/// build script's `arm_long_multiply`) one `mla` written out: left to the
/// compiler, a value walked this way became a stepped sum again, which the
/// pixel loops keep live and spill.
#[inline(always)]
pub fn word_mul_add(acc: i32, n: u32, d: i32) -> i32 {
    #[cfg(arm_long_multiply)]
    {
        let sum: i32;
        // SAFETY: register-only arithmetic, no memory, stack or flags.
        unsafe {
            core::arch::asm!(
                "mla {sum}, {n}, {d}, {acc}",
                sum = lateout(reg) sum,
                n = in(reg) n,
                d = in(reg) d,
                acc = in(reg) acc,
                options(pure, nomem, nostack, preserves_flags)
            );
        }
        sum
    }
    #[cfg(not(arm_long_multiply))]
    {
        acc.wrapping_add((n as i32).wrapping_mul(d))
    }
}

/// `i`, through an empty `asm!` statement: the compiler no longer knows
/// how it was computed. A loop whose index passes through it has no turn
/// count the compiler can work out, so it is not unrolled. The z-buffer's
/// runs take it ([`crate::shading::ColorWalk::UNROLLED_RUNS`]): unrolled
/// two pixels a turn, each row paid about 40 instructions of set-up for
/// runs of three or four pixels. So does its whole-band test's scan of a
/// row's depths, which mostly stops within a few pixels. On targets
/// without stable inline assembly, `i` as it is.
#[inline(always)]
pub fn uncounted(i: usize) -> usize {
    // Left as it is where the statement below is not compiled.
    #[allow(unused_mut)]
    let mut i = i;
    #[cfg(any(
        target_arch = "arm",
        target_arch = "aarch64",
        target_arch = "x86",
        target_arch = "x86_64",
        target_arch = "riscv32",
        target_arch = "riscv64"
    ))]
    // SAFETY: an empty statement (a comment naming the register): no
    // instruction, memory, stack or flags.
    unsafe {
        core::arch::asm!("/* {i} */", i = inout(reg) i, options(pure, nomem, nostack, preserves_flags));
    }
    i
}

/// The products of the signed low half-words of `x` and `y` and of their
/// signed high half-words, added: one `smuad` on Armv7E-M (the build
/// script's `arm_dual_multiply`: Cortex-M4 and M7), plain multiplication
/// elsewhere (the same value). The sum must fit `i32`. Written in Rust with
/// half-word operands, the compiler makes two instructions of it (`smulbb`,
/// `smlatb`), and the coverage masks that take it cost the teapot's frame
/// 0.37 M instructions more.
#[inline(always)]
pub fn dual_mul_add(x: u32, y: u32) -> i32 {
    #[cfg(arm_dual_multiply)]
    {
        let sum: i32;
        // SAFETY: register-only arithmetic, no memory or stack. `smuad` sets
        // the Q flag only where the sum overflows, which the caller rules out.
        unsafe {
            core::arch::asm!(
                "smuad {sum}, {x}, {y}",
                sum = lateout(reg) sum,
                x = in(reg) x,
                y = in(reg) y,
                options(pure, nomem, nostack, preserves_flags)
            );
        }
        sum
    }
    #[cfg(not(arm_dual_multiply))]
    {
        let low = |v: u32| v as i16 as i32;
        let high = |v: u32| (v >> 16) as i16 as i32;
        low(x) * low(y) + high(x) * high(y)
    }
}

/// `a * b >> shift` with rounding to nearest, in 64 bits.
#[inline]
pub const fn mul_shift_round(a: i64, b: i64, shift: u32) -> i64 {
    (a * b + (1 << (shift - 1))) >> shift
}

/// Saturates an `i64` into `[-limit, limit]`.
#[inline]
pub const fn saturate(v: i64, limit: i64) -> i64 {
    if v > limit {
        limit
    } else if v < -limit {
        -limit
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::xorshift;

    #[test]
    fn isqrt_exact_and_floor() {
        for n in 0u64..10_000 {
            let r = isqrt_u64(n);
            assert!(r * r <= n && (r + 1) * (r + 1) > n, "n={n}");
        }
        assert_eq!(isqrt_u64(u64::MAX), u32::MAX as u64);
        assert_eq!(isqrt_u64(1 << 62), 1 << 31);
    }

    #[test]
    fn large_divisor_first_matches_mul_div() {
        // Window positions: numerators of up to 2^38 in magnitude, divisors
        // of any size below that, every extra scale up to setup's.
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        for _ in 0..200_000 {
            let d = (next() >> (next() % 64).max(26)).max(1);
            let n = (next() as i64) >> (25 + next() % 39);
            let extra = (next() % 27) as u32;
            let r = Reciprocal::new(d);
            assert_eq!(
                r.mul_div_large_divisor(n, extra),
                r.mul_div(n, extra),
                "{n} * 2^{extra} / {d}"
            );
        }
    }

    #[test]
    fn reciprocal_divides_within_its_error_bound() {
        let mut next = xorshift(0x2545_f491_4f6c_dd1d);
        for _ in 0..200_000 {
            let d = (next() >> (next() % 64).max(2)).max(1) & ((1 << 62) - 1);
            let d = d.max(1);
            let n = (next() as i64) >> (2 + next() % 60);
            let extra = (next() % 31) as u32;
            let exact = ((n as i128) << extra).div_euclid(d as i128);
            if exact.unsigned_abs() >= 1 << 62 {
                continue;
            }
            let got = Reciprocal::new(d).mul_div(n, extra) as i128;
            let tolerance = (exact.abs() >> 29) + 2 + (1i128 << extra.min(62)) / d as i128;
            assert!(
                (got - exact).abs() <= tolerance,
                "{n} * 2^{extra} / {d}: {got} vs {exact}"
            );
        }
        // Rounded down, a few units below the exact quotient at most.
        let q = Reciprocal::new(1).divide(1 << 40);
        assert!((1 << 40) - q < 1 << 12, "{q}");
        assert!((98..=100).contains(&Reciprocal::new(3).divide(300)));
    }

    #[test]
    fn a_shift_below_32_word_by_word_is_the_64_bit_shift() {
        let mut next = xorshift(0x3c6e_f372_fe94_f82b);
        for _ in 0..100_000 {
            let v = next() as i64 >> (next() % 64);
            for s in 0..32 {
                assert_eq!(shift_below_32(v, s), v >> s, "{v} >> {s}");
            }
        }
    }

    #[test]
    fn every_path_divides_as_the_two_halves_do() {
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        let edges = [
            0i64,
            1,
            -1,
            (1 << 31) - 1,
            -(1 << 31) + 1,
            1 << 30,
            -(1 << 30),
        ];
        for i in 0..400_000 {
            let d = ((next() >> (next() % 64).max(2)) & ((1 << 62) - 1)).max(1);
            let n = match i % 4 {
                0 => edges[(next() % edges.len() as u64) as usize],
                1 => (next() as i64) >> (2 + next() % 62),
                _ => (next() as i64) >> (32 + next() % 32),
            };
            let extra = (next() % 48) as u32;
            // Only quotients that fit (as `mul_div` asks).
            if ((n as i128) << extra).div_euclid(d as i128).unsigned_abs() >= 1 << 60 {
                continue;
            }
            let r = Reciprocal::new(d);
            let wide = r.mul_div_wide(n, extra);
            assert_eq!(r.mul_div(n, extra), wide, "{n} * 2^{extra} / {d}");
            let pair = [n, (next() as i64) >> (32 + next() % 32)];
            let each = r.mul_div_each(pair, extra);
            for (k, &n) in pair.iter().enumerate() {
                let wide = r.mul_div_wide(n, extra);
                if wide.unsigned_abs() < 1 << 62 {
                    assert_eq!(each[k], wide, "{n} * 2^{extra} / {d}, in a pair");
                }
            }
            // Numerators that fit a word: the word path gives the same bits.
            if pair.iter().all(|n| n.unsigned_abs() < 1 << 31) {
                let words = pair.map(|n| n as i32);
                let fits = pair
                    .iter()
                    .all(|&n| r.mul_div_wide(n, extra).unsigned_abs() < 1 << 62);
                if fits {
                    assert_eq!(r.mul_div_each_word(words, extra), each, "{pair:?} / {d}");
                }
            }
        }
    }

    #[test]
    fn sin_cos_matches_float() {
        let mut d = -720.0f64;
        while d <= 720.0 {
            let (s, c) = sin_cos_deg(Coord::from_num(d));
            let r = Coord::from_num(d).to_num::<f64>().to_radians();
            assert!(
                (s as f64 / Q30 as f64 - r.sin()).abs() < 2e-8,
                "sin {d} {} {}",
                s as f64 / Q30 as f64,
                r.sin()
            );
            assert!((c as f64 / Q30 as f64 - r.cos()).abs() < 2e-8, "cos {d}");
            d += 0.37;
        }
    }
}
