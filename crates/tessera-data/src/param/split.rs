//! The eight outcomes of one LOD step (paper E §4.1, Fig. 5) and the patches they produce.
//! The rules are stated in the [`super::lod`] module doc.

use super::lod::Patch;

/// The eight outcomes of one LOD step (paper E Fig. 5). Children order is documented per variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SplitPattern {
    /// No split: the patch is rendered.
    Keep = 0,
    /// v halves: lower, upper.
    HalveV = 1,
    /// u halves: lower, upper.
    HalveU = 2,
    /// Four quarters: (u lo, v lo), (u hi, v lo), (u lo, v hi), (u hi, v hi).
    Quarter = 3,
    /// v halves, the lower one halved in u: (u lo, v lo), (u hi, v lo), (all u, v hi).
    HalveVSplitLowerU = 4,
    /// v halves, the upper one halved in u: (all u, v lo), (u lo, v hi), (u hi, v hi).
    HalveVSplitUpperU = 5,
    /// u halves, the lower one halved in v: (u lo, v lo), (u lo, v hi), (u hi, all v).
    HalveUSplitLowerV = 6,
    /// u halves, the upper one halved in v: (u lo, all v), (u hi, v lo), (u hi, v hi).
    HalveUSplitUpperV = 7,
}

impl SplitPattern {
    /// The outcome for the split flags of the four u-lines and the four v-lines.
    pub fn decide(split_u_lines: [bool; 4], split_v_lines: [bool; 4]) -> SplitPattern {
        let a = split_u_lines[0] || split_u_lines[1];
        let b = split_u_lines[2] || split_u_lines[3];
        let c = split_v_lines[0] || split_v_lines[1];
        let d = split_v_lines[2] || split_v_lines[3];
        if (c && d) || (a != b) {
            match (a, b) {
                (false, false) => SplitPattern::HalveV,
                (true, true) => SplitPattern::Quarter,
                (true, false) => SplitPattern::HalveVSplitLowerU,
                (false, true) => SplitPattern::HalveVSplitUpperU,
            }
        } else if (a && b) || (c != d) {
            match (c, d) {
                (true, false) => SplitPattern::HalveUSplitLowerV,
                (false, true) => SplitPattern::HalveUSplitUpperV,
                _ => SplitPattern::HalveU,
            }
        } else {
            SplitPattern::Keep
        }
    }

    /// `(u part, v part)` of each child in the documented order: 0 = lower half, 1 = upper
    /// half, 2 = whole range.
    pub(crate) fn pieces(self) -> &'static [(u8, u8)] {
        match self {
            SplitPattern::Keep => &[(2, 2)],
            SplitPattern::HalveV => &[(2, 0), (2, 1)],
            SplitPattern::HalveU => &[(0, 2), (1, 2)],
            SplitPattern::Quarter => &[(0, 0), (1, 0), (0, 1), (1, 1)],
            SplitPattern::HalveVSplitLowerU => &[(0, 0), (1, 0), (2, 1)],
            SplitPattern::HalveVSplitUpperU => &[(2, 0), (0, 1), (1, 1)],
            SplitPattern::HalveUSplitLowerV => &[(0, 0), (0, 1), (1, 2)],
            SplitPattern::HalveUSplitUpperV => &[(0, 2), (1, 0), (1, 1)],
        }
    }

    /// The patches this pattern turns `patch` into (`[patch]` for `Keep`).
    pub fn children(self, patch: &Patch) -> Vec<Patch> {
        self.pieces()
            .iter()
            .map(|&(pu, pv)| Patch::new(part(patch.u, pu), part(patch.v, pv), patch.object))
            .collect()
    }

    /// The number a shader would use for this outcome (0 = keep, see the variants).
    pub fn code(self) -> u32 {
        self as u32
    }
}

/// Lower half, upper half or the whole of `r`.
pub(crate) fn part(r: [f32; 2], which: u8) -> [f32; 2] {
    let mid = midpoint(r);
    match which {
        0 => [r[0], mid],
        1 => [mid, r[1]],
        _ => r,
    }
}

fn midpoint(r: [f32; 2]) -> f32 {
    r[0] + (r[1] - r[0]) * 0.5
}

pub(crate) fn halvable(r: [f32; 2]) -> bool {
    let mid = midpoint(r);
    r[0] < mid && mid < r[1]
}

#[cfg(test)]
#[path = "split_tests.rs"]
mod tests;
