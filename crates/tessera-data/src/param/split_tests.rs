//! Tests of `split`.
use super::*;

fn overlap(a: [f32; 2], b: [f32; 2]) -> bool {
    a[0].max(b[0]) < a[1].min(b[1])
}

/// All 256 flag combinations: every flagged line's half is split along the line, the children
/// tile the parent, and the paper's example (a u-line at v1) gives the 3-patch pattern.
#[test]
fn split_patterns_honour_every_flag() {
    let unit = Patch::new([0.0, 1.0], [0.0, 1.0], 0);
    let line_pos = |k: usize| 0.25 * (k as f32 + 0.5);
    let mut seen = std::collections::HashSet::new();
    for bits in 0..256_u32 {
        let su = [0, 1, 2, 3].map(|k| bits & (1 << k) != 0);
        let sv = [0, 1, 2, 3].map(|k| bits & (16 << k) != 0);
        let pattern = SplitPattern::decide(su, sv);
        seen.insert(pattern);
        let children = pattern.children(&unit);
        assert_eq!(pattern == SplitPattern::Keep, bits == 0);
        let total: f64 = children.iter().map(Patch::area).sum();
        assert_eq!(total, 1.0);
        for (i, a) in children.iter().enumerate() {
            for b in &children[i + 1..] {
                assert!(!(overlap(a.u, b.u) && overlap(a.v, b.v)), "{pattern:?}");
            }
        }
        for k in 0..4 {
            let at = line_pos(k);
            for c in &children {
                if su[k] && c.v[0] <= at && at <= c.v[1] {
                    assert_eq!(c.u[1] - c.u[0], 0.5, "u-line {k}, {pattern:?}");
                }
                if sv[k] && c.u[0] <= at && at <= c.u[1] {
                    assert_eq!(c.v[1] - c.v[0], 0.5, "v-line {k}, {pattern:?}");
                }
            }
        }
    }
    assert_eq!(seen.len(), 8);
    let only_v1 = SplitPattern::decide([true, false, false, false], [false; 4]);
    assert_eq!(only_v1, SplitPattern::HalveVSplitLowerU);
    assert_eq!(only_v1.code(), 4);
    assert_eq!(
        SplitPattern::decide([true; 4], [false; 4]),
        SplitPattern::HalveU
    );
    assert_eq!(
        SplitPattern::decide([false; 4], [false, false, true, false]),
        SplitPattern::HalveUSplitUpperV
    );
}

#[test]
fn children_split_at_exact_midpoints() {
    let p = Patch::new([0.1, 0.7], [2.0, 3.0], 5);
    let c = SplitPattern::HalveVSplitUpperU.children(&p);
    // The documented f32 midpoint u0 + (u1 - u0) * 0.5, not the decimal 0.4.
    let m = 0.1_f32 + (0.7_f32 - 0.1) * 0.5;
    assert_eq!(
        c,
        vec![
            Patch::new([0.1, 0.7], [2.0, 2.5], 5),
            Patch::new([0.1, m], [2.5, 3.0], 5),
            Patch::new([m, 0.7], [2.5, 3.0], 5),
        ]
    );
    assert_eq!(SplitPattern::Keep.children(&p), vec![p]);
    assert!(!halvable([1.0, f32::from_bits(1.0_f32.to_bits() + 1)]));
    assert!(halvable([1.0, f32::from_bits(1.0_f32.to_bits() + 2)]));
}
