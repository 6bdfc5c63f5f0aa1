//! SPEC sections 3 to 5 on a single pixel: insertion with visibility masks, and the
//! three overflow policies, on hand-made cases and against a reference model of one
//! pixel's fragment list (property test).

use abuffer_test_support::FragmentStorage;
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::Mask4x4;
use mcu_abuffer::fragment::Fragment;
use mcu_abuffer::fragment_buffer::{BufferConfig, OverflowPolicy};
use mcu_abuffer::stats::BufferStats;
use proptest::prelude::*;
use system_tests::{channels, fragment, rgb888, rgb_of};

type F = Fragment<Mask4x4>;

/// A plain copy of a fragment for comparisons and messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Plain {
    mask: u16,
    z: u32,
    dzdx: i32,
    dzdy: i32,
    rgb: [u8; 3],
}

impl Plain {
    fn of(f: &F) -> Self {
        Self {
            mask: f.mask.0,
            z: f.z,
            dzdx: f.dzdx,
            dzdy: f.dzdy,
            rgb: rgb_of(f),
        }
    }

    fn to_fragment(self) -> F {
        fragment(Mask4x4(self.mask), self.z, self.dzdx, self.dzdy, self.rgb)
    }

    fn k(&self) -> u64 {
        self.mask.count_ones() as u64
    }

    /// Depth at sample `s` scaled by 16, with the sample offsets of SPEC section 2
    /// computed here: `(2i + 1 - 4) / 8` pixel = `(2i - 3) * 2` sixteenths.
    fn depth16(&self, s: u32) -> i64 {
        let (i, j) = ((s % 4) as i64, (s / 4) as i64);
        16 * self.z as i64 + self.dzdx as i64 * (2 * i - 3) * 2 + self.dzdy as i64 * (2 * j - 3) * 2
    }
}

/// SPEC section 4, written out: `a` nearer, `b` farther.
fn merged(a: &Plain, b: &Plain) -> Plain {
    let (ka, kb) = (a.k(), b.k());
    let k = ka + kb;
    let smaller = |ga: i32, gb: i32| {
        if ga.unsigned_abs() < gb.unsigned_abs() {
            ga
        } else {
            gb
        }
    };
    // Round to nearest (halves up).
    let rgb = core::array::from_fn(|c| {
        let sum = a.rgb[c] as u64 * ka + b.rgb[c] as u64 * kb;
        ((2 * sum + k) / (2 * k)) as u8
    });
    Plain {
        mask: a.mask | b.mask,
        z: a.z + ((b.z - a.z) as u64 * kb / k) as u32,
        dzdx: smaller(a.dzdx, b.dzdx),
        dzdy: smaller(a.dzdy, b.dzdy),
        rgb,
    }
}

/// One pixel: a fragment buffer of width 1 and one row.
struct Pixel {
    storage: FragmentStorage<Mask4x4>,
}

impl Pixel {
    fn new(main: u8, extra: u8, pool: usize, policy: OverflowPolicy) -> Self {
        let config = BufferConfig {
            width: 1,
            band_height: 1,
            main_slots: main,
            extra_addresses: extra,
            policy,
        };
        Self {
            storage: FragmentStorage::new(config, pool),
        }
    }

    /// Inserts the fragments in order; returns the list (nearest first), the stats and
    /// the pool slots in use.
    fn run(&mut self, frags: &[Plain]) -> (Vec<Plain>, BufferStats, usize) {
        let mut b = self.storage.buffer();
        b.begin_band(0, 1);
        for f in frags {
            b.insert(0, 0, &f.to_fragment());
        }
        let list = b.fragments(0, 0).map(|f| Plain::of(&f)).collect();
        (list, b.stats(), b.pool().in_use())
    }
}

/// The two ways to give a pixel room for two fragments, plus a pool too small for
/// the addresses (SPEC section 5: "or the pool is full").
const CAPACITY_TWO: [(u8, u8, usize); 3] = [(2, 0, 0), (1, 1, 1), (1, 2, 1)];

fn plain(mask: u16, z: u32, dzdx: i32, dzdy: i32, rgb: [u8; 3]) -> Plain {
    Plain {
        mask,
        z,
        dzdx,
        dzdy,
        rgb,
    }
}

fn permutations3() -> [[usize; 3]; 6] {
    [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ]
}

/// Three disjoint fragments (nearest first).
fn three() -> [Plain; 3] {
    [
        plain(0x000F, 1000, -50, 30, [200, 10, 0]),
        plain(0x0FF0, 2000, 20, -30, [0, 90, 11]),
        plain(0x3000, 3000, -20, 5, [101, 100, 255]),
    ]
}

#[test]
fn merge_farthest_three_disjoint_any_order() {
    let t = three();
    // Hand-computed: K = 8 and 2; z = 2000 + 1000 * 2 / 10 = 2200; dzdx tie
    // |20| = |-20| takes the farther's -20; dzdy 5; colors (0*8 + 101*2)/10 = 20.2 -> 20,
    // (90*8 + 100*2)/10 = 92, (11*8 + 255*2)/10 = 59.8 -> 60.
    let m = plain(0x3FF0, 2200, -20, 5, [20, 92, 60]);
    assert_eq!(merged(&t[1], &t[2]), m);
    for (main, extra, pool) in CAPACITY_TWO {
        for order in permutations3() {
            let frags = order.map(|i| t[i]);
            let mut px = Pixel::new(main, extra, pool, OverflowPolicy::MergeFarthest);
            let (list, stats, in_use) = px.run(&frags);
            let what = format!("main {main} extra {extra} pool {pool}, arrival {order:?}");
            assert_eq!(list, vec![t[0], m], "{what}");
            assert_eq!(stats.merges, 1, "{what}");
            assert_eq!(stats.fragments_discarded, 0, "{what}");
            assert_eq!(stats.fragments_generated, 3, "{what}");
            assert_eq!(in_use, 2 - main as usize, "{what}");
        }
    }
}

#[test]
fn merge_rounding_and_weights() {
    // 1 sample against 3: z = 100 + 400 * 3 / 4 = 400; colors (10 + 3*13)/4 = 12.25 -> 12,
    // (0 + 3*1)/4 = 0.75 -> 1, (255 + 0)/4 = 63.75 -> 64; the nearer has the smaller
    // gradients.
    let a = plain(0x0001, 100, 3, -4, [10, 0, 255]);
    let b = plain(0x0700, 500, -7, 9, [13, 1, 0]);
    let c = plain(0x0080, 50, 0, 0, [0, 0, 0]);
    let want = plain(0x0701, 400, 3, -4, [12, 1, 64]);
    assert_eq!(merged(&a, &b), want);
    let mut px = Pixel::new(1, 1, 1, OverflowPolicy::MergeFarthest);
    let (list, _, _) = px.run(&[a, b, c]);
    assert_eq!(list, vec![c, want]);
    // A half rounds up: (1*1 + 2*1)/2 = 1.5 -> 2.
    let d = plain(0x0001, 10, 0, 0, [1, 1, 1]);
    let e = plain(0x0002, 20, 0, 0, [2, 2, 2]);
    let near = plain(0x0004, 5, 0, 0, [0, 0, 0]);
    let mut px = Pixel::new(2, 0, 0, OverflowPolicy::MergeFarthest);
    let (list, _, _) = px.run(&[d, e, near]);
    assert_eq!(list[1].rgb, [2, 2, 2]);
    assert_eq!(list[1].z, 15);
}

#[test]
fn merge_closest_picks_the_pair_nearest_in_depth() {
    // Gaps 300 (first pair) and 1700 (second pair): the first pair merges.
    let t = [
        plain(0x000F, 1000, -50, 30, [200, 10, 0]),
        plain(0x0FF0, 1300, 20, -30, [0, 90, 11]),
        plain(0x3000, 3000, -20, 5, [101, 100, 255]),
    ];
    let near_pair = merged(&t[0], &t[1]);
    // Gaps 1700 and 300: the second pair merges.
    let u = [
        plain(0x000F, 1000, -50, 30, [200, 10, 0]),
        plain(0x0FF0, 2700, 20, -30, [0, 90, 11]),
        plain(0x3000, 3000, -20, 5, [101, 100, 255]),
    ];
    let far_pair = merged(&u[1], &u[2]);
    for (main, extra, pool) in CAPACITY_TWO {
        for order in permutations3() {
            let what = format!("main {main} extra {extra} pool {pool}, arrival {order:?}");
            let mut px = Pixel::new(main, extra, pool, OverflowPolicy::MergeClosest);
            let (list, stats, _) = px.run(&order.map(|i| t[i]));
            assert_eq!(list, vec![near_pair, t[2]], "{what}");
            assert_eq!(stats.merges, 1, "{what}");
            let (list, stats, _) = px.run(&order.map(|i| u[i]));
            assert_eq!(list, vec![u[0], far_pair], "{what}");
            assert_eq!(stats.merges, 1, "{what}");
        }
    }
}

#[test]
fn discard_drops_the_smaller_of_the_two_farthest() {
    let near = plain(0x000F, 1000, 0, 0, [1, 2, 3]);
    let cases = [
        // (middle, farthest, survivor among them)
        (
            plain(0x0FF0, 2000, 0, 0, [4, 5, 6]),
            plain(0x3000, 3000, 0, 0, [7, 8, 9]),
            0,
        ),
        (
            plain(0x0030, 2000, 0, 0, [4, 5, 6]),
            plain(0xFF00, 3000, 0, 0, [7, 8, 9]),
            1,
        ),
        // Equal coverage: the farther one goes.
        (
            plain(0x00F0, 2000, 0, 0, [4, 5, 6]),
            plain(0x0F00, 3000, 0, 0, [7, 8, 9]),
            0,
        ),
    ];
    for (mid, far, keep) in cases {
        let t = [near, mid, far];
        let survivor = if keep == 0 { mid } else { far };
        for (main, extra, pool) in CAPACITY_TWO {
            for order in permutations3() {
                let what = format!(
                    "main {main} extra {extra} pool {pool}, arrival {order:?}, mid {mid:?} far {far:?}"
                );
                let mut px = Pixel::new(main, extra, pool, OverflowPolicy::Discard);
                let (list, stats, in_use) = px.run(&order.map(|i| t[i]));
                assert_eq!(list, vec![near, survivor], "{what}");
                assert_eq!(stats.fragments_discarded, 1, "{what}");
                assert_eq!(stats.merges, 0, "{what}");
                assert_eq!(in_use, 2 - main as usize, "{what}");
            }
        }
    }
}

/// Per-sample comparison of SPEC section 3: the new fragment keeps the samples
/// where it is nearer or equally near.
fn expected_split(new: &Plain, old: &Plain) -> (u16, u16) {
    let (mut keep_new, mut keep_old) = (new.mask, old.mask);
    for s in 0..16 {
        let bit = 1u16 << s;
        if new.mask & old.mask & bit != 0 {
            if new.depth16(s) <= old.depth16(s) {
                keep_old &= !bit;
            } else {
                keep_new &= !bit;
            }
        }
    }
    (keep_new, keep_old)
}

#[test]
fn intersecting_planes_split_the_samples() {
    // A tilts down to the right and up towards the bottom; B the other way.
    let a = plain(0xFFFF, 5000, 800, -300, [255, 0, 0]);
    let b = plain(0xFFFF, 5100, -200, 500, [0, 0, 255]);
    for (first, second) in [(a, b), (b, a)] {
        let (keep_new, keep_old) = expected_split(&second, &first);
        assert!(
            keep_new != 0 && keep_old != 0,
            "the planes must cross in the pixel"
        );
        assert_eq!(keep_new | keep_old, 0xFFFF);
        let mut px = Pixel::new(1, 1, 1, OverflowPolicy::MergeFarthest);
        let (list, stats, _) = px.run(&[first, second]);
        let mut masks: Vec<(u32, u16)> = list.iter().map(|f| (f.z, f.mask)).collect();
        masks.sort_unstable();
        let mut want = vec![(second.z, keep_new), (first.z, keep_old)];
        want.sort_unstable();
        assert_eq!(masks, want, "first {first:?} then {second:?}");
        assert_eq!(stats.merges, 0);
    }
}

#[test]
fn depth_ties_go_to_the_newer_fragment() {
    // Per sample (x 16): A = 16000 + 16 * ox, B = 16032: equal at ox = 2 (column 2).
    let a = plain(0xFFFF, 1000, 16, 0, [255, 0, 0]);
    let b = plain(0xFFFF, 1002, 0, 0, [0, 0, 255]);
    let mut px = Pixel::new(2, 0, 0, OverflowPolicy::MergeFarthest);
    // A arrives second: it wins columns 0, 1 and 2 (the tie).
    let (list, _, _) = px.run(&[b, a]);
    assert_eq!(
        list.iter().map(|f| f.mask).collect::<Vec<_>>(),
        vec![0x7777, 0x8888]
    );
    // B arrives second: it wins columns 2 (the tie) and 3.
    let (list, _, _) = px.run(&[a, b]);
    assert_eq!(
        list.iter().map(|f| f.mask).collect::<Vec<_>>(),
        vec![0x3333, 0xCCCC]
    );
    // A coplanar copy takes every sample from the stored one, which is removed.
    let c = plain(0xFFFF, 1002, 0, 0, [0, 255, 0]);
    let (list, stats, _) = px.run(&[b, c]);
    assert_eq!(list, vec![c]);
    assert_eq!(stats.fragments_removed_hidden, 1);
}

#[test]
fn resolve_weights_colors_by_coverage() {
    // 4 red samples, 8 blue, 4 background (0, 255, 0):
    // r = (255*4 + 8) >> 4 = 64, g = (255*4 + 8) >> 4 = 64, b = (255*8 + 8) >> 4 = 128.
    let mut px = Pixel::new(2, 0, 0, OverflowPolicy::MergeFarthest);
    let mut b = px.storage.buffer();
    b.begin_band(0, 1);
    b.insert(0, 0, &plain(0x000F, 10, 0, 0, [255, 0, 0]).to_fragment());
    b.insert(0, 0, &plain(0x0FF0, 20, 0, 0, [0, 0, 255]).to_fragment());
    let mut out = [rgb888([0, 0, 0])];
    b.resolve_row(0, rgb888([0, 255, 0]), &mut out);
    assert_eq!(channels(out[0]), [64, 64, 128]);
}

/// A row resolves pixel by pixel whatever its width: covered pixels in and
/// out of four-pixel groups, groups with nothing, and a last group cut short.
#[test]
fn resolve_row_covers_every_pixel_of_any_width() {
    let background = [0, 255, 0];
    for width in 1..=11u16 {
        let config = BufferConfig {
            width,
            band_height: 2,
            main_slots: 2,
            extra_addresses: 0,
            policy: OverflowPolicy::MergeFarthest,
        };
        let mut storage = FragmentStorage::<Mask4x4>::new(config, 0);
        let mut b = storage.buffer();
        b.begin_band(0, 2);
        let drawn = |x: u16| x.is_multiple_of(5) || x == width - 1 || x == 6;
        let color = |x: u16| [10 * x as u8, 3, 200 - x as u8];
        for x in (0..width).filter(|&x| drawn(x)) {
            b.insert(x, 1, &plain(0xFFFF, 10, 0, 0, color(x)).to_fragment());
        }
        for row in 0..2 {
            let mut out = vec![rgb888([1, 2, 3]); width as usize];
            b.resolve_row(row, rgb888(background), &mut out);
            for x in 0..width {
                let expected = if row == 1 && drawn(x) {
                    color(x)
                } else {
                    background
                };
                assert_eq!(
                    channels(out[x as usize]),
                    expected,
                    "width {width}, {x}, {row}"
                );
            }
        }
    }
}

/// The whole-band test's summary of strips of columns agrees with the pixels:
/// it says "hidden" only once every pixel of the strips is covered by nearer
/// fragments, never under `Discard` (which drops coverage), and answers the
/// same as asking every pixel.
#[test]
fn strip_summary_hides_only_what_every_pixel_hides() {
    for policy in [
        OverflowPolicy::MergeFarthest,
        OverflowPolicy::SplitBands,
        OverflowPolicy::Discard,
    ] {
        let config = BufferConfig {
            width: 20,
            band_height: 3,
            main_slots: 1,
            extra_addresses: 2,
            policy,
        };
        let mut storage = FragmentStorage::<Mask4x4>::new(config, 64);
        let mut b = storage.buffer();
        // The summary is kept from the band after the frame's first question.
        b.begin_band(0, 3);
        assert!(!b.hides_columns(0, 7, i64::MAX));
        b.begin_band(3, 3);
        let every_pixel = |b: &mut mcu_abuffer::FragmentBuffer<'_, Mask4x4, u32>,
                           x0: u16,
                           x1: u16,
                           depth: i64| {
            (0..3).all(|row| (x0..=x1).all(|x| b.hides(x, row, depth)))
        };
        // Columns 0..8 (strip 0): two half masks per pixel at depths 100 and
        // 120, tilted (the farthest sample of the second is 16 * 120 + 6 * 12).
        for row in 0..3 {
            for x in 0..8 {
                b.insert(x, row, &plain(0x00FF, 100, 0, 0, [9, 9, 9]).to_fragment());
                assert!(!b.hides_columns(0, 7, i64::MAX), "strip full too early");
                b.insert(x, row, &plain(0xFF00, 120, 6, 0, [9, 9, 9]).to_fragment());
            }
        }
        let farthest = 16 * 120 + 6 * 6;
        let kept = policy != OverflowPolicy::Discard;
        assert_eq!(b.hides_columns(0, 7, farthest + 1), kept, "{policy:?}");
        assert!(every_pixel(&mut b, 0, 7, farthest + 1));
        // Not strictly nearer: not hidden, by the strip or by any pixel.
        assert!(!b.hides_columns(0, 7, farthest));
        assert!(!every_pixel(&mut b, 0, 7, farthest));
        // Strip 1 (columns 8..16) is empty: a box reaching into it is not hidden.
        assert!(!b.hides_columns(3, 9, farthest + 1));
        // A new band starts empty.
        b.begin_band(6, 3);
        assert!(!b.hides_columns(0, 7, i64::MAX));
        // A new frame (the band at row 0) forgets the earlier frame's
        // questions: its first band answers pixel by pixel, so a frame does
        // the same work however many frames came before it.
        b.begin_band(0, 3);
        for row in 0..3 {
            for x in 0..8 {
                b.insert(x, row, &plain(0xFFFF, 100, 0, 0, [9, 9, 9]).to_fragment());
            }
        }
        assert!(every_pixel(&mut b, 0, 7, 16 * 100 + 1));
        assert!(!b.hides_columns(0, 7, 16 * 100 + 1), "{policy:?}");
    }
}

// ---------------------------------------------------------------------------------
// Reference model of one pixel
// ---------------------------------------------------------------------------------

#[derive(Default)]
struct Model {
    list: Vec<Plain>,
    merges: u64,
    discarded: u64,
    /// A tie the SPEC leaves open (equal center depths, equal gaps) happened.
    ambiguous: bool,
}

impl Model {
    fn insert(
        &mut self,
        new: Plain,
        main: usize,
        extra: usize,
        pool: usize,
        policy: OverflowPolicy,
    ) {
        let mut f = new;
        for old in self.list.iter_mut() {
            let (keep_new, keep_old) = expected_split(&f, old);
            f.mask = keep_new;
            old.mask = keep_old;
        }
        self.list.retain(|o| o.mask != 0);
        if f.mask == 0 {
            return;
        }
        if self.list.iter().any(|o| o.z == f.z) {
            self.ambiguous = true;
        }
        let k = self
            .list
            .iter()
            .position(|o| o.z > f.z)
            .unwrap_or(self.list.len());
        let n = self.list.len();
        let pool_used = n.saturating_sub(main);
        let fits = n < main || (n < main + extra && pool_used < pool);
        let mut l = self.list.clone();
        l.insert(k, f);
        if fits {
            self.list = l;
            return;
        }
        match policy {
            OverflowPolicy::MergeFarthest => {
                let m = merged(&l[n - 1], &l[n]);
                l.splice(n - 1..=n, [m]);
                self.merges += 1;
            }
            OverflowPolicy::MergeClosest | OverflowPolicy::SplitBands => {
                let gaps: Vec<u32> = (0..n).map(|i| l[i + 1].z - l[i].z).collect();
                let best = *gaps.iter().min().unwrap();
                if gaps.iter().filter(|&&g| g == best).count() > 1 {
                    self.ambiguous = true;
                }
                let i = gaps.iter().position(|&g| g == best).unwrap();
                let m = merged(&l[i], &l[i + 1]);
                l.splice(i..=i + 1, [m]);
                self.merges += 1;
            }
            OverflowPolicy::Discard => {
                let drop = if l[n].k() <= l[n - 1].k() { n } else { n - 1 };
                l.remove(drop);
                self.discarded += 1;
            }
        }
        self.list = l;
    }
}

fn policy_of(i: u8) -> OverflowPolicy {
    [
        OverflowPolicy::MergeFarthest,
        OverflowPolicy::MergeClosest,
        OverflowPolicy::Discard,
    ][i as usize % 3]
}

fn arb_fragment() -> impl Strategy<Value = Plain> {
    (
        prop_oneof![
            Just(0xFFFFu16),
            1u16..=0xFFFF,
            (0u32..16).prop_map(|s| 1u16 << s)
        ],
        1000u32..1400,
        -300i32..=300,
        -300i32..=300,
        any::<[u8; 3]>(),
    )
        .prop_map(|(mask, z, dzdx, dzdy, rgb)| plain(mask, z, dzdx, dzdy, rgb))
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 6000,
        // Failures print the minimal input; no regression files in the source tree.
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// After every insertion the pixel's list equals the reference model's: per-sample
    /// visibility, removal of hidden fragments, sorted insertion, and the overflow
    /// policy when `N_main + N_extra` or the pool runs out.
    #[test]
    fn pixel_matches_reference_model(
        frags in prop::collection::vec(arb_fragment(), 1..12),
        main in 1u8..=3,
        extra in 0u8..=3,
        pool in 0usize..=3,
        policy in 0u8..3,
    ) {
        let policy = policy_of(policy);
        let mut px = Pixel::new(main, extra, pool, policy);
        let mut model = Model::default();
        for i in 0..frags.len() {
            model.insert(frags[i], main as usize, extra as usize, pool, policy);
            if model.ambiguous {
                break;
            }
            let (list, stats, in_use) = px.run(&frags[..=i]);
            prop_assert_eq!(&list, &model.list, "after {} insertions of {:?}", i + 1, &frags[..=i]);
            prop_assert_eq!(u64::from(stats.merges), model.merges);
            prop_assert_eq!(u64::from(stats.fragments_discarded), model.discarded);
            prop_assert_eq!(in_use, list.len().saturating_sub(main as usize));
        }
    }
}
