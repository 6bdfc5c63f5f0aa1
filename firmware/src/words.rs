//! Rows of pixels and depths moved and filled 32-bit words at a time, six
//! or eight to a step: the Cortex-M core then stores them with
//! store-multiples (or pairs), where the compiler's `memcpy` and `memset`
//! take one word at a time with a loop's overhead on each. Used where a
//! frame moves whole rows: a z-buffer's rows copied into the sink's line,
//! its depths and colors and the A-buffer's fragment counts set at the
//! start of each band, the A-buffer's runs of background pixels.

/// `bytes` as the bytes before its first word boundary, the whole words
/// after it and the bytes after the last whole word.
#[inline(always)]
fn as_words_mut(bytes: &mut [u8]) -> (&mut [u8], &mut [u32], &mut [u8]) {
    // SAFETY: every bit pattern is a `u32`, and the words borrow `bytes`
    // for no longer than `bytes` itself.
    unsafe { bytes.align_to_mut::<u32>() }
}

/// Copies `src` into `dst` (of the same length), eight 32-bit words at a
/// time where the two lines lie alike against word boundaries, so that the
/// Cortex-M core moves them with a load-multiple and a store-multiple
/// (about 1.35 instructions a word, against 4 in the compiler's `memcpy`);
/// byte by byte where they do not.
#[inline(never)]
pub fn copy_bytes(dst: &mut [u8], src: &[u8]) {
    // SAFETY: as in `as_words_mut`, for a shared borrow.
    let (src_head, src_words, src_tail) = unsafe { src.align_to::<u32>() };
    let (dst_head, dst_words, dst_tail) = as_words_mut(dst);
    if dst_head.len() != src_head.len() || dst_words.len() != src_words.len() {
        dst.copy_from_slice(src);
        return;
    }
    dst_head.copy_from_slice(src_head);
    let mut to = dst_words.chunks_exact_mut(8);
    let mut from = src_words.chunks_exact(8);
    for (to, from) in (&mut to).zip(&mut from) {
        // Element by element: the compiler pairs the loads and the stores
        // into multiples (a copy of the chunk as one array calls `memcpy`).
        let words = [
            from[0], from[1], from[2], from[3], from[4], from[5], from[6], from[7],
        ];
        for (to, word) in to.iter_mut().zip(words) {
            *to = word;
        }
    }
    for (to, &from) in to.into_remainder().iter_mut().zip(from.remainder()) {
        *to = from;
    }
    dst_tail.copy_from_slice(src_tail);
}

/// Sets every word of `dst` to `value`, eight words to a step.
#[inline(never)]
pub fn fill_words(dst: &mut [u32], value: u32) {
    let mut steps = dst.chunks_exact_mut(8);
    for step in &mut steps {
        for word in step.iter_mut() {
            *word = value;
        }
    }
    for word in steps.into_remainder() {
        *word = value;
    }
}

/// Sets every byte of `dst` to `value`: the whole words among them by
/// [`fill_words`], out of line. ([`fill_repeating`] with a one-byte unit
/// gives the same bytes, but inlined with a constant unit its loop is what
/// the compiler turns back into a call of `memset`.)
#[inline]
pub fn fill_bytes(dst: &mut [u8], value: u8) {
    let (head, words, tail) = as_words_mut(dst);
    head.fill(value);
    fill_words(words, u32::from_ne_bytes([value; 4]));
    tail.fill(value);
}

/// Fills `dst` with copies of the `N` bytes of `unit`, from its start (a
/// partial copy at the end): the whole words among them six to a step, from
/// a pattern of three words (twelve bytes, a whole number of units).
#[inline]
pub fn fill_repeating<const N: usize>(dst: &mut [u8], unit: [u8; N]) {
    const { assert!(N > 0 && 12 % N == 0) };
    let (head, words, tail) = as_words_mut(dst);
    for (k, byte) in head.iter_mut().enumerate() {
        *byte = unit[k % N];
    }
    // The three words that repeat from the first word boundary on.
    let phase = head.len();
    let pattern: [u32; 3] = core::array::from_fn(|w| {
        u32::from_ne_bytes(core::array::from_fn(|b| unit[(phase + 4 * w + b) % N]))
    });
    let mut steps = words.chunks_exact_mut(6);
    for step in &mut steps {
        for (word, &value) in step.iter_mut().zip(pattern.iter().cycle()) {
            *word = value;
        }
    }
    for (word, &value) in steps
        .into_remainder()
        .iter_mut()
        .zip(pattern.iter().cycle())
    {
        *word = value;
    }
    let after = phase + 4 * words.len();
    for (k, byte) in tail.iter_mut().enumerate() {
        *byte = unit[(after + k) % N];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every length and every offset of the two lines against word
    /// boundaries: the copy is the bytes, whether they go as words or not.
    #[test]
    fn bytes_copy_whole_at_every_alignment() {
        let source: [u8; 128] = core::array::from_fn(|i| (i * 7 + 3) as u8);
        for len in 0..90 {
            for from in 0..4 {
                for to in 0..4 {
                    let mut target = [0xAAu8; 128];
                    copy_bytes(&mut target[to..to + len], &source[from..from + len]);
                    assert_eq!(target[to..to + len], source[from..from + len]);
                    assert!(target[..to].iter().all(|&b| b == 0xAA));
                    assert!(target[to + len..].iter().all(|&b| b == 0xAA));
                }
            }
        }
    }

    #[test]
    fn every_word_is_filled_and_no_other() {
        for len in 0..40 {
            let mut words = [7u32; 48];
            fill_words(&mut words[3..3 + len], u32::MAX);
            assert!(words[3..3 + len].iter().all(|&w| w == u32::MAX));
            assert!(words[..3].iter().chain(&words[3 + len..]).all(|&w| w == 7));
        }
    }

    #[test]
    fn every_byte_is_filled_and_no_other() {
        for len in 0..40 {
            for from in 0..4 {
                let mut bytes = [7u8; 48];
                fill_bytes(&mut bytes[from..from + len], 0xC3);
                assert!(bytes[from..from + len].iter().all(|&b| b == 0xC3));
                assert!(bytes[..from]
                    .iter()
                    .chain(&bytes[from + len..])
                    .all(|&b| b == 7));
            }
        }
    }

    #[test]
    fn units_repeat_from_the_start_at_every_alignment() {
        fn check<const N: usize>(unit: [u8; N]) {
            for len in 0..60 {
                for from in 0..4 {
                    let mut bytes = [0xEEu8; 72];
                    fill_repeating(&mut bytes[from..from + len], unit);
                    for (k, &b) in bytes[from..from + len].iter().enumerate() {
                        assert_eq!(b, unit[k % N], "unit {unit:?} length {len} offset {from}");
                    }
                    assert!(bytes[..from]
                        .iter()
                        .chain(&bytes[from + len..])
                        .all(|&b| b == 0xEE));
                }
            }
        }
        check([1, 2, 3]);
        check([0xF8, 0x1F]);
        check([5]);
        check([1, 2, 3, 4]);
    }
}
