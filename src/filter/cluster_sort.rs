//! Sorting mean shift's `(bin, point index)` keys through one `u64` each.

/// Sorts `items` as `sort_unstable` would (lexicographically; the point index makes every
/// item unique, so the order is the one order), through one `u64` per item when the bins'
/// ranges and the largest index fit in 64 bits together — a few times faster than comparing
/// tuples, and a belief's bins span a few hundred at most. `packed` is scratch.
pub(super) fn sort_keys<const F: usize>(items: &mut [([i64; F], u32)], packed: &mut Vec<u64>) {
    let Some(&(first, _)) = items.first() else {
        return;
    };
    let (mut lo, mut hi, mut last) = (first, first, 0u32);
    for (key, i) in items.iter() {
        for f in 0..F {
            lo[f] = lo[f].min(key[f]);
            hi[f] = hi[f].max(key[f]);
        }
        last = last.max(*i);
    }
    let bits = |span: u64| 64 - span.leading_zeros();
    let mut widths = [0u32; F];
    for f in 0..F {
        widths[f] = bits(hi[f].abs_diff(lo[f]));
    }
    let index_bits = bits(u64::from(last));
    if widths.iter().sum::<u32>() + index_bits > 64 {
        items.sort_unstable();
        return;
    }
    packed.clear();
    packed.extend(items.iter().map(|(key, i)| {
        let mut p = 0u64;
        for f in 0..F {
            p = (p << widths[f]) | key[f].abs_diff(lo[f]);
        }
        (p << index_bits) | u64::from(*i)
    }));
    packed.sort_unstable();
    for (item, &p) in items.iter_mut().zip(packed.iter()) {
        item.1 = (p & low_mask(index_bits)) as u32;
        let mut rest = p >> index_bits;
        for f in (0..F).rev() {
            item.0[f] = lo[f].wrapping_add_unsigned(rest & low_mask(widths[f]));
            rest >>= widths[f];
        }
    }
}

/// The lowest `bits` bits set (none for 0, all for 64).
fn low_mask(bits: u32) -> u64 {
    if bits >= 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::RngExt;

    #[test]
    fn packed_sorting_is_tuple_sorting() {
        let mut rng = crate::random::stream(3, 0, 0);
        let mut packed = Vec::new();
        for case in 0..300 {
            let span: i64 = [1, 5, 300, 1 << 20, i64::MAX / 4][case % 5];
            let n = rng.random_range(0..400);
            let mut items: Vec<([i64; 3], u32)> = (0..n)
                .map(|i| {
                    let mut k = [0i64; 3];
                    for v in &mut k {
                        *v = rng.random_range(-span..=span);
                    }
                    (k, i as u32 * 3)
                })
                .collect();
            let mut expected = items.clone();
            expected.sort_unstable();
            sort_keys(&mut items, &mut packed);
            assert_eq!(items, expected, "case {case}");
        }
    }
}
