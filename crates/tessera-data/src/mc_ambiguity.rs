//! How marching cubes cuts an ambiguous face: one whose above-iso corners are diagonal, so
//! the surface may either join them across the face or separate them. The decision picks a
//! row of [`crate::mc_tables`]; it looks at the face's four values only, in an order fixed
//! by the face (not by the cell), so both cells sharing a face decide alike.

use crate::mc_tables::{corner_below, mc_tables, FACE_CORNERS};

/// The rule for ambiguous faces.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub enum AmbiguityRule {
    /// The asymptotic decider (Nielson and Hamann): the bilinear interpolant of the face's
    /// corners has a saddle; the above corners are joined when the saddle value is `>= iso`,
    /// which is how the interpolated field itself connects them.
    #[default]
    AsymptoticDecider,
    /// VTK's fixed convention (`vtkMarchingCubes`, `vtkFlyingEdges3D`): the above corners
    /// are always separated, whatever the values.
    Vtk,
}

impl AmbiguityRule {
    /// `decider` or `vtk`, as the command line names them.
    pub fn parse(text: &str) -> crate::error::Result<AmbiguityRule> {
        match text {
            "decider" => Ok(AmbiguityRule::AsymptoticDecider),
            "vtk" => Ok(AmbiguityRule::Vtk),
            _ => Err(crate::error::DataError::Invalid(format!(
                "ambiguous faces '{text}': choose decider (the asymptotic decider) or vtk \
                 (VTK's fixed convention)"
            ))),
        }
    }

    /// Bit `f` set when the above corners of ambiguous face `f` are to be joined, for a cell
    /// of `case` whose corner values are `values` (indexed by corner). Bits of faces that
    /// are not ambiguous are zero.
    pub fn joined_faces(self, case: u8, values: &[f32; 8], iso: f32) -> u8 {
        match self {
            AmbiguityRule::Vtk => 0,
            AmbiguityRule::AsymptoticDecider => {
                let ambiguous = mc_tables().ambiguous_faces[usize::from(case)];
                (0..6)
                    .filter(|&f| ambiguous >> f & 1 == 1)
                    .filter(|&f| {
                        saddle_is_above(case, FACE_CORNERS[f].map(usize::from), values, iso)
                    })
                    .fold(0, |m, f| m | 1 << f)
            }
        }
    }
}

/// Whether the saddle of the bilinear interpolant over the ambiguous face with `corners`
/// (in the face's order, diagonals 0–3 and 1–2) lies at or above `iso`.
///
/// With `d = value - iso`, the saddle value minus iso is
/// `(d0 d3 - d1 d2) / (d0 + d3 - d1 - d2)`, and the denominator has the sign of the above
/// diagonal; so the saddle is above exactly when the above diagonal's product is at least
/// the below diagonal's. Products instead of the quotient keep the test to two rounded
/// subtractions and one rounded product per diagonal, which the shaders repeat exactly
/// (`mc_cell.glsl`), and the `>=` matches the classification of a value equal to iso.
pub fn saddle_is_above(case: u8, corners: [usize; 4], values: &[f32; 8], iso: f32) -> bool {
    let d = corners.map(|c| values[c] - iso);
    let main = d[0] * d[3];
    let anti = d[1] * d[2];
    if corner_below(case, corners[0]) {
        anti >= main
    } else {
        main >= anti
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case_of(values: &[f32; 8], iso: f32) -> u8 {
        (0..8).fold(0, |m, c| m | u8::from(values[c] < iso) << c)
    }

    #[test]
    fn decider_follows_the_saddle_value() {
        // Face z = 0 with 1 on the diagonal 0–3 and 0 on 1–2: the saddle value is 0.5.
        let mut values = [0.0; 8];
        values[0] = 1.0;
        values[3] = 1.0;
        for (iso, joined) in [(0.2, true), (0.5, true), (0.8, false)] {
            let case = case_of(&values, iso);
            assert_eq!(mc_tables().ambiguous_faces[usize::from(case)], 1 << 4);
            let bits = AmbiguityRule::AsymptoticDecider.joined_faces(case, &values, iso);
            assert_eq!(bits == 1 << 4, joined, "iso {iso}");
            assert_eq!(AmbiguityRule::Vtk.joined_faces(case, &values, iso), 0);
        }
    }

    #[test]
    fn decision_matches_the_quotient_form_on_the_anti_diagonal_too() {
        // Above corners on the 1–2 diagonal; saddle = (ad - bc) / (a + d - b - c).
        let (a, b, c, d) = (0.1f32, 0.9, 0.7, 0.3);
        let saddle = (a * d - b * c) / (a + d - b - c);
        for iso in [0.35, 0.45, 0.55, 0.6] {
            let values = [a, b, c, d, 0.0, 0.0, 0.0, 0.0];
            let case = case_of(&values, iso);
            assert_eq!(
                mc_tables().ambiguous_faces[usize::from(case)] & 1 << 4,
                1 << 4
            );
            assert_eq!(
                saddle_is_above(case, [0, 1, 2, 3], &values, iso),
                saddle >= iso,
                "iso {iso}, saddle {saddle}"
            );
        }
    }
}
