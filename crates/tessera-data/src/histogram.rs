//! Value histograms of volumes and the isovalue a user gets when they name none: Otsu's
//! threshold, the value that best splits the histogram into two classes (the largest
//! between-class variance). On CT data that is the boundary between air and tissue or
//! tissue and bone rather than the middle of the value range.

use crate::volume::{Samples, Volume};

/// Bins of the histogram [`otsu_isovalue`] looks at. Enough to resolve 8-bit data exactly.
pub const OTSU_BINS: usize = 256;

/// Counts of `volume`'s samples in `bins` equal bins over its value range (`bins` ≥ 1; a
/// constant volume puts everything in bin 0).
pub fn histogram(volume: &Volume, bins: usize) -> Vec<u64> {
    let bins = bins.max(1);
    let (lo, hi) = volume.value_range();
    let mut counts = vec![0u64; bins];
    let width = f64::from(hi) - f64::from(lo);
    let bin_of = |v: f32| -> usize {
        if width <= 0.0 {
            return 0;
        }
        let t = (f64::from(v) - f64::from(lo)) / width;
        ((t * bins as f64) as usize).min(bins - 1)
    };
    match volume.samples() {
        Samples::U8(values) => values.iter().for_each(|&v| counts[bin_of(v.into())] += 1),
        Samples::U16(values) => values.iter().for_each(|&v| counts[bin_of(v.into())] += 1),
        Samples::F32(values) => values.iter().for_each(|&v| counts[bin_of(v)] += 1),
    }
    counts
}

/// Otsu's threshold of a histogram: the number `k` of leading bins that form the lower class
/// when the split maximises the between-class variance (1 ≤ k < bins). `None` when no split
/// separates anything (fewer than two occupied bins).
pub fn otsu_split(counts: &[u64]) -> Option<usize> {
    let total: f64 = counts.iter().map(|&c| c as f64).sum();
    let weighted: f64 = counts
        .iter()
        .enumerate()
        .map(|(i, &c)| i as f64 * c as f64)
        .sum();
    let (mut below, mut below_weighted) = (0.0f64, 0.0f64);
    let mut best: Option<(usize, f64)> = None;
    for (k, &c) in counts
        .iter()
        .enumerate()
        .take(counts.len().saturating_sub(1))
    {
        below += c as f64;
        below_weighted += k as f64 * c as f64;
        let above = total - below;
        if below == 0.0 || above == 0.0 {
            continue;
        }
        let mean_below = below_weighted / below;
        let mean_above = (weighted - below_weighted) / above;
        let variance = below * above * (mean_below - mean_above).powi(2);
        // Ties (empty bins between two classes) keep the middle of the gap.
        match best {
            Some((_, v)) if variance < v => {}
            Some((first, v)) if variance == v => best = Some((first, v)),
            _ => best = Some((k + 1, variance)),
        }
    }
    let (split, _) = best?;
    // Centre the split in any run of empty bins it starts, so that the threshold lies
    // halfway between the two classes.
    let mut end = split;
    while end < counts.len() && counts[end] == 0 {
        end += 1;
    }
    let mut start = split;
    while start > 0 && counts[start - 1] == 0 {
        start -= 1;
    }
    Some((start + end).div_ceil(2).clamp(1, counts.len() - 1))
}

/// The isovalue (raw units) at Otsu's threshold of `volume`'s histogram: the boundary between
/// the two classes; integer data gets a half-integer so that no sample equals it. `None` for
/// a volume that has a single value.
pub fn otsu_isovalue(volume: &Volume) -> Option<f32> {
    let (lo, hi) = volume.value_range();
    if hi <= lo {
        return None;
    }
    let integer = !matches!(volume.samples(), Samples::F32(_));
    // Integer data of a small range gets one bin per value.
    let bins = if integer && hi - lo < OTSU_BINS as f32 {
        (hi - lo) as usize + 1
    } else {
        OTSU_BINS
    };
    let split = otsu_split(&histogram(volume, bins))?;
    let value = f64::from(lo) + (f64::from(hi) - f64::from(lo)) * split as f64 / bins as f64;
    Some(if integer {
        (value.floor() + 0.5).clamp(f64::from(lo) + 0.5, f64::from(hi) - 0.5) as f32
    } else {
        value as f32
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn volume_u8(values: Vec<u8>) -> Volume {
        let n = values.len() as u32;
        Volume::new("h", [n / 4, 2, 2], [1.0; 3], Samples::U8(values)).unwrap()
    }

    #[test]
    fn histogram_counts_every_sample_once() {
        let v = volume_u8((0..16).map(|i| i * 17).collect());
        let h = histogram(&v, 4);
        assert_eq!(h, vec![4, 4, 4, 4]);
        assert_eq!(histogram(&v, 1), vec![16]);
        let constant = volume_u8(vec![7; 8]);
        assert_eq!(histogram(&constant, 3), vec![8, 0, 0]);
    }

    #[test]
    fn otsu_splits_two_clusters_in_the_gap() {
        // 10 samples at bins 1-2, 6 at bins 7-8: the gap is bins 3..=6.
        let mut counts = vec![0u64; 10];
        counts[1] = 6;
        counts[2] = 4;
        counts[7] = 2;
        counts[8] = 4;
        let k = otsu_split(&counts).unwrap();
        assert!((4..=6).contains(&k), "split {k}");
        assert_eq!(otsu_split(&[0, 5, 0]), None);
        assert_eq!(otsu_split(&[3, 5]), Some(1));
    }

    #[test]
    fn otsu_prefers_the_larger_jump_over_the_middle() {
        // Air (value 10, many), tissue (100), bone (250, few): the threshold between air and
        // tissue, far below the middle of the range (130).
        let mut values = vec![10u8; 40];
        values.extend([100u8; 20]);
        values.extend([250u8; 4]);
        let v = volume_u8(values);
        let iso = otsu_isovalue(&v).unwrap();
        assert!(iso > 10.0 && iso < 100.0, "iso {iso}");
        assert_eq!(iso.fract(), 0.5);
    }

    #[test]
    fn otsu_of_float_and_constant_volumes() {
        let values: Vec<f32> = (0..32)
            .map(|i| if i < 20 { -300.0 } else { 700.0 })
            .collect();
        let v = Volume::new("f", [8, 2, 2], [1.0; 3], Samples::F32(values)).unwrap();
        let iso = otsu_isovalue(&v).unwrap();
        assert!(iso > -300.0 && iso < 700.0, "iso {iso}");
        assert_eq!(otsu_isovalue(&volume_u8(vec![3; 8])), None);
    }
}
