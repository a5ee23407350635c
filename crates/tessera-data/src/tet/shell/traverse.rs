//! Shell-to-shell traversal (paper B, Alg. 1): find the exit face of the volume segment ahead
//! with front faces culled, cast the ray backwards from there for the segment's entry face,
//! march the segment, then go on past the exit for the next segment of a non-convex mesh.
//! Starting from the exit face is what lets the ray origin lie inside the mesh: the entry face
//! is then behind it, and the tets before the origin are marched but not reported.

use glam::DVec3;

use super::layouts::TetLayout;
use super::march::{march, MarchEnd, MarchStart};
use super::projection::RayBasis;
use super::shell_hits::shell_hits;
use super::ShellMesh;
use crate::tet::topology::NO_NEIGHBOUR;

/// A ray in world space: the part `t_min ≤ t ≤ t_max` of `origin + t * dir`. Distances are
/// measured along `dir` normalized, so `t` is a length whatever `dir`'s own length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
    pub t_min: f64,
    pub t_max: f64,
}

impl Ray {
    /// The whole ray ahead of `origin`, `dir` normalized (zero when it has no length).
    pub fn new(origin: DVec3, dir: DVec3) -> Ray {
        Ray {
            origin,
            dir: dir.normalize_or_zero(),
            t_min: 0.0,
            t_max: f64::INFINITY,
        }
    }
}

/// One tet crossed: its stretch of the ray, clipped to `[t_min, t_max]`, and the vertex ids
/// of the face the ray entered it through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    pub tet: u32,
    pub t_enter: f64,
    pub t_exit: f64,
    pub entered_face: [u32; 3],
}

/// How a segment ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentEnd {
    /// At the shell.
    Shell,
    /// The visitor stopped the traversal (early termination, end of the ray).
    Stopped,
    /// The loop guard: no exit face, corrupt ids, or too many steps.
    Guard,
}

/// The tets of one volume segment in ray order.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    pub steps: Vec<Step>,
    pub end: SegmentEnd,
}

/// Limits of the traversal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TraversalOptions {
    /// Steps one segment may take before the loop guard ends it. The paper breaks loops
    /// "after a few iterations"; a bound per segment keeps a circling ray finite without
    /// cutting honest long rays short.
    pub max_steps_per_segment: u64,
}

impl Default for TraversalOptions {
    fn default() -> Self {
        TraversalOptions {
            max_steps_per_segment: 1 << 16,
        }
    }
}

/// Counts over many rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalStats {
    pub rays: u64,
    pub segments: u64,
    /// Tets marched through, including those before `t_min`.
    pub steps: u64,
    /// Segments the loop guard ended because no exit face was found or a layout yielded ids
    /// out of range.
    pub dead_ends: u64,
    /// Segments the loop guard ended at the step limit.
    pub step_limits: u64,
    /// Steps whose exit lay before their entry (inverted or flat tets); not an error alone.
    pub backward_steps: u64,
    /// Exit faces found without an entry face before them (a shell that is not closed).
    pub unmatched_exits: u64,
}

impl TraversalStats {
    /// Segments the loop guard ended.
    pub fn guard_hits(&self) -> u64 {
        self.dead_ends + self.step_limits
    }

    pub fn add(&mut self, other: &TraversalStats) {
        self.rays += other.rays;
        self.segments += other.segments;
        self.steps += other.steps;
        self.dead_ends += other.dead_ends;
        self.step_limits += other.step_limits;
        self.backward_steps += other.backward_steps;
        self.unmatched_exits += other.unmatched_exits;
    }
}

/// What a traversal reports to.
pub trait StepVisitor {
    /// Tet `step` of segment `segment` (numbered from 0 among the segments within the ray's
    /// range); false stops the whole traversal.
    fn step(&mut self, segment: usize, step: &Step) -> bool;

    /// Segment `segment` ended after at least one step was reported.
    fn segment_end(&mut self, _segment: usize, _end: SegmentEnd) {}
}

impl<F: FnMut(usize, &Step) -> bool> StepVisitor for F {
    fn step(&mut self, segment: usize, step: &Step) -> bool {
        self(segment, step)
    }
}

/// Traverses `ray` through `shell` with tets read from `layout` (built from the same shell
/// mesh), reporting each tet the ray crosses within its range to `visit`, in order. A ray
/// with an unusable direction crosses nothing.
pub fn traverse(
    shell: &ShellMesh,
    layout: &dyn TetLayout,
    ray: &Ray,
    options: &TraversalOptions,
    stats: &mut TraversalStats,
    visit: &mut impl StepVisitor,
) {
    stats.rays += 1;
    let Some(basis) = RayBasis::new(ray.origin, ray.dir) else {
        return;
    };
    let hits = shell_hits(shell, &basis);
    let mut from = 0;
    let mut segment = 0;
    // Trace with front faces culled: the nearest exit beyond t_min, past the last segment.
    while let Some(exit) = (from..hits.len()).find(|&i| hits[i].leaves && hits[i].t > ray.t_min) {
        // The backward trace from the exit point, front faces (of the reversed ray) culled.
        // Past the first segment it stops at the previous exit (a t_max on the GPU), so a
        // shell that is not closed cannot send it back into a segment already marched.
        let floor = from;
        from = exit + 1;
        let Some(entry) = (floor..exit).rev().find(|&i| !hits[i].leaves) else {
            stats.unmatched_exits += 1;
            continue;
        };
        let entry = hits[entry];
        if entry.t >= ray.t_max {
            return;
        }
        let face = &shell.faces[entry.face as usize];
        // Outward winding has the entering ray on the right of each edge: reverse it.
        let [a, b, c] = face
            .vertices
            .map(|v| basis.project(v, shell.world[v as usize]));
        let start = MarchStart {
            tet: face.tet,
            came_from: NO_NEIGHBOUR,
            face: [a, c, b],
            t_enter: entry.t,
        };
        let mut stopped = false;
        let mut reported = false;
        let outcome = march(
            layout,
            &shell.world,
            &basis,
            start,
            options.max_steps_per_segment,
            |step| {
                if step.t_enter >= ray.t_max {
                    stopped = true;
                    return false;
                }
                if step.t_exit <= ray.t_min {
                    return true;
                }
                reported = true;
                let clipped = Step {
                    t_enter: step.t_enter.max(ray.t_min),
                    t_exit: step.t_exit.min(ray.t_max),
                    ..*step
                };
                let go_on = visit.step(segment, &clipped);
                stopped = !go_on;
                go_on
            },
        );
        stats.steps += outcome.steps;
        stats.backward_steps += outcome.backward_steps;
        let end = match outcome.end {
            MarchEnd::DeadEnd => {
                stats.dead_ends += 1;
                SegmentEnd::Guard
            }
            MarchEnd::StepLimit => {
                stats.step_limits += 1;
                SegmentEnd::Guard
            }
            MarchEnd::Shell => SegmentEnd::Shell,
            MarchEnd::Stopped => SegmentEnd::Stopped,
        };
        if reported {
            visit.segment_end(segment, end);
            stats.segments += 1;
            segment += 1;
        }
        if stopped {
            return;
        }
    }
}

/// [`traverse`] collecting the segments (those with at least one tet within the ray's range)
/// and how each ended.
pub fn trace_segments(
    shell: &ShellMesh,
    layout: &dyn TetLayout,
    ray: &Ray,
    options: &TraversalOptions,
    stats: &mut TraversalStats,
) -> Vec<Segment> {
    let mut collector = SegmentCollector(Vec::new());
    traverse(shell, layout, ray, options, stats, &mut collector);
    collector.0
}

struct SegmentCollector(Vec<Segment>);

impl StepVisitor for SegmentCollector {
    fn step(&mut self, segment: usize, step: &Step) -> bool {
        if segment == self.0.len() {
            self.0.push(Segment {
                steps: Vec::new(),
                end: SegmentEnd::Shell,
            });
        }
        self.0[segment].steps.push(*step);
        true
    }

    fn segment_end(&mut self, segment: usize, end: SegmentEnd) {
        if let Some(s) = self.0.get_mut(segment) {
            s.end = end;
        }
    }
}
