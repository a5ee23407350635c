//! Tet marching (paper B, Alg. 2) through one volume segment: from the face the ray entered
//! by, recover the tet's fourth vertex from the layout, decide the exit face in ray space and
//! step to the neighbour behind it, until the shell.

use glam::DVec3;

use super::layouts::TetLayout;
use super::projection::{crossing_distance, ray_left_of, Projected, RayBasis};
use super::traverse::Step;
use crate::tet::topology::NO_NEIGHBOUR;

/// Where marching starts: the tet behind the entered face, the tet on the other side of that
/// face (or [`NO_NEIGHBOUR`] from the shell) and the face's vertices ordered so the ray passes
/// on the left of each edge (counter-clockwise in ray space).
#[derive(Clone, Copy, Debug)]
pub(crate) struct MarchStart {
    pub tet: u32,
    pub came_from: u32,
    pub face: [Projected; 3],
    pub t_enter: f64,
}

/// Why marching stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MarchEnd {
    /// The ray left through a shell face: the segment is done.
    Shell,
    /// The visitor asked to stop (early termination, or past the end of the ray).
    Stopped,
    /// The ray found no exit face, or the layout yielded ids out of range: a degenerate or
    /// inconsistent tet.
    DeadEnd,
    /// More steps than allowed: the ray circled through degenerate tets.
    StepLimit,
}

/// What marching reports besides the steps.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MarchOutcome {
    pub end: MarchEnd,
    pub steps: u64,
    /// Steps whose exit lay before their entry: inverted or flat tets crossed.
    pub backward_steps: u64,
}

/// Marches from `start`, calling `visit` for every tet crossed (in order); `visit` returns
/// false to stop.
pub(crate) fn march(
    layout: &dyn TetLayout,
    vertices: &[DVec3],
    basis: &RayBasis,
    start: MarchStart,
    max_steps: u64,
    mut visit: impl FnMut(&Step) -> bool,
) -> MarchOutcome {
    let mut outcome = MarchOutcome {
        end: MarchEnd::StepLimit,
        steps: 0,
        backward_steps: 0,
    };
    let MarchStart {
        mut tet,
        mut came_from,
        mut face,
        mut t_enter,
    } = start;
    while outcome.steps < max_steps {
        outcome.steps += 1;
        let entered = face.map(|p| p.id);
        let Some(decoded) = layout.decode(tet, came_from, entered) else {
            outcome.end = MarchEnd::DeadEnd;
            return outcome;
        };
        let apex_id = decoded.vertices[3];
        let Some(&apex_position) = vertices.get(apex_id as usize) else {
            outcome.end = MarchEnd::DeadEnd;
            return outcome;
        };
        let apex = basis.project(apex_id, apex_position);
        let Some((opposite, next_face)) = exit_face(&apex, &face) else {
            outcome.end = MarchEnd::DeadEnd;
            return outcome;
        };
        let t_exit = crossing_distance(&next_face[0], &next_face[1], &next_face[2]);
        if t_exit < t_enter {
            outcome.backward_steps += 1;
        }
        let step = Step {
            tet,
            t_enter,
            t_exit,
            entered_face: entered,
        };
        if !visit(&step) {
            outcome.end = MarchEnd::Stopped;
            return outcome;
        }
        let next = decoded.neighbours[opposite];
        if next == NO_NEIGHBOUR {
            outcome.end = MarchEnd::Shell;
            return outcome;
        }
        if next as usize >= layout.tet_count() {
            outcome.end = MarchEnd::DeadEnd;
            return outcome;
        }
        (came_from, tet, face, t_enter) = (tet, next, next_face, t_exit);
    }
    outcome
}

/// The exit face of a tet entered through `face` (counter-clockwise about the ray) whose
/// fourth vertex is `apex`: the index (0..3) of the face vertex opposite it and the exit face,
/// again counter-clockwise about the ray, apex first. The three edges from the apex to the
/// face's corners split the entered triangle into three sectors; the ray lies in the one whose
/// first edge has it on the left and whose second on the right. `None` when it lies in none
/// (all three on one side): only a degenerate or inverted tet does that.
pub(crate) fn exit_face(
    apex: &Projected,
    face: &[Projected; 3],
) -> Option<(usize, [Projected; 3])> {
    let left = [0, 1, 2].map(|i| ray_left_of(apex, &face[i]));
    (0..3).find_map(|i| {
        let j = (i + 1) % 3;
        (left[i] && !left[j]).then(|| ((i + 2) % 3, [*apex, face[i], face[j]]))
    })
}
