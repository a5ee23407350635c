//! A bounding volume hierarchy over the shell triangles (paper B, §4: the shell-BVH), built by
//! binned surface-area heuristic and flattened into one array of nodes that a GPU walks with a
//! small stack. Children of a node sit next to each other, so a node names only its first.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::ShellMesh;

/// Deepest level a node may sit at (the root is level 0): a walk needs a stack of one more
/// entry than this. A range that reaches it becomes a leaf, however many faces it holds.
pub const BVH_MAX_DEPTH: u32 = 40;

/// Faces a leaf holds at most where the builder may still split.
pub const BVH_LEAF_FACES: usize = 4;

/// Centroid bins the surface-area heuristic tries per axis.
const BINS: usize = 16;

/// Cost of visiting a node relative to testing one face, in the surface-area heuristic.
const NODE_COST: f32 = 1.0;

/// One node as the GPU reads it (std430: `vec3 lo; uint first; vec3 hi; uint count;`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub lo: [f32; 3],
    /// An inner node's first child (the second follows it); a leaf's first face in
    /// [`ShellBvh::faces`].
    pub first: u32,
    pub hi: [f32; 3],
    /// Faces in a leaf; 0 marks an inner node.
    pub count: u32,
}

/// The flattened hierarchy: node 0 is the root.
#[derive(Clone, Debug, PartialEq)]
pub struct ShellBvh {
    pub nodes: Vec<BvhNode>,
    /// Indices into [`ShellMesh::faces`] in leaf order: leaf `n` holds
    /// `faces[n.first .. n.first + n.count]`.
    pub faces: Vec<u32>,
    /// Deepest level of a node (0 for a root that is a leaf).
    pub depth: u32,
}

impl ShellMesh {
    /// The BVH over this mesh's shell faces in world space. Each box is widened a little,
    /// so a ray grazing a face along the box's edge in `f32` still enters it.
    pub fn bvh(&self) -> ShellBvh {
        let boxes: Vec<(Vec3, Vec3)> = self
            .faces
            .iter()
            .map(|f| {
                let p = f.vertices.map(|v| self.world[v as usize].as_vec3());
                (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
            })
            .collect();
        build_bvh(&boxes)
    }
}

/// The BVH over primitives with bounding boxes `boxes` (`(lo, hi)` each), every box padded by
/// a millionth of the scene's extent plus a margin for the coordinates' magnitude.
pub fn build_bvh(boxes: &[(Vec3, Vec3)]) -> ShellBvh {
    let mut builder = Builder {
        boxes: boxes.to_vec(),
        centroids: boxes.iter().map(|(lo, hi)| (*lo + *hi) * 0.5).collect(),
        order: (0..boxes.len() as u32).collect(),
        nodes: vec![BvhNode::default()],
        depth: 0,
    };
    // Without boxes the root is a leaf without faces whose box is inverted (lo > hi); the GPU
    // upload refuses an empty shell before any walk.
    let (lo, hi) = builder.bounds(0, boxes.len());
    let pad = 1e-6 * (hi - lo).max_element() + 1e-6 * lo.abs().max(hi.abs()).max_element();
    for b in &mut builder.boxes {
        *b = (b.0 - Vec3::splat(pad), b.1 + Vec3::splat(pad));
    }
    builder.build(0, 0, boxes.len(), 0);
    ShellBvh {
        nodes: builder.nodes,
        faces: builder.order,
        depth: builder.depth,
    }
}

struct Builder {
    boxes: Vec<(Vec3, Vec3)>,
    centroids: Vec<Vec3>,
    /// Primitive ids, permuted so each node's are contiguous.
    order: Vec<u32>,
    nodes: Vec<BvhNode>,
    depth: u32,
}

/// Half the surface area of a box (the heuristic compares ratios only).
fn half_area(lo: Vec3, hi: Vec3) -> f32 {
    let d = (hi - lo).max(Vec3::ZERO);
    d.x * d.y + d.y * d.z + d.z * d.x
}

impl Builder {
    fn bounds(&self, start: usize, end: usize) -> (Vec3, Vec3) {
        self.order[start..end].iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| {
                let b = self.boxes[p as usize];
                (lo.min(b.0), hi.max(b.1))
            },
        )
    }

    /// Fills node `node` with the primitives `order[start..end]` at level `level`.
    fn build(&mut self, node: usize, start: usize, end: usize, level: u32) {
        self.depth = self.depth.max(level);
        let (lo, hi) = self.bounds(start, end);
        let leaf = BvhNode {
            lo: lo.to_array(),
            first: start as u32,
            hi: hi.to_array(),
            count: (end - start) as u32,
        };
        let split = if end - start > BVH_LEAF_FACES && level < BVH_MAX_DEPTH {
            self.split(start, end, half_area(lo, hi))
        } else {
            None
        };
        let Some(mid) = split else {
            self.nodes[node] = leaf;
            return;
        };
        let first = self.nodes.len();
        self.nodes.push(BvhNode::default());
        self.nodes.push(BvhNode::default());
        self.nodes[node] = BvhNode {
            first: first as u32,
            count: 0,
            ..leaf
        };
        self.build(first, start, mid, level + 1);
        self.build(first + 1, mid, end, level + 1);
    }

    /// Partitions `order[start..end]` at the cheapest binned plane and returns where the
    /// second half starts; `None` when keeping a leaf is cheaper. Primitives whose centroids
    /// coincide are halved by count, so the depth limit is the only way to a large leaf.
    fn split(&mut self, start: usize, end: usize, area: f32) -> Option<usize> {
        let (c_lo, c_hi) = self.order[start..end].iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| {
                let c = self.centroids[p as usize];
                (lo.min(c), hi.max(c))
            },
        );
        let extent = c_hi - c_lo;
        let count = end - start;
        if extent.max_element() <= 0.0 {
            self.order[start..end].sort_unstable();
            return Some(start + count / 2);
        }
        let bin_of = |c: Vec3, axis: usize| -> usize {
            let u = (c[axis] - c_lo[axis]) / extent[axis] * BINS as f32;
            (u as usize).min(BINS - 1)
        };
        // (cost, axis, bins left of the plane)
        let mut best: Option<(f32, usize, usize)> = None;
        for axis in 0..3 {
            if extent[axis] <= 0.0 {
                continue;
            }
            let empty = (
                Vec3::splat(f32::INFINITY),
                Vec3::splat(f32::NEG_INFINITY),
                0,
            );
            let mut bins = [empty; BINS];
            for &p in &self.order[start..end] {
                let b = &mut bins[bin_of(self.centroids[p as usize], axis)];
                let (lo, hi) = self.boxes[p as usize];
                *b = (b.0.min(lo), b.1.max(hi), b.2 + 1);
            }
            // Areas and counts of everything left of each plane, then right of it.
            let mut left = [(0.0f32, 0usize); BINS];
            let mut acc = empty;
            for i in 0..BINS - 1 {
                acc = (
                    acc.0.min(bins[i].0),
                    acc.1.max(bins[i].1),
                    acc.2 + bins[i].2,
                );
                left[i] = (half_area(acc.0, acc.1), acc.2);
            }
            let mut acc = empty;
            for i in (1..BINS).rev() {
                acc = (
                    acc.0.min(bins[i].0),
                    acc.1.max(bins[i].1),
                    acc.2 + bins[i].2,
                );
                let (area_left, n_left) = left[i - 1];
                if n_left == 0 || acc.2 == 0 {
                    continue;
                }
                let cost = NODE_COST
                    + (area_left * n_left as f32 + half_area(acc.0, acc.1) * acc.2 as f32)
                        / area.max(f32::MIN_POSITIVE);
                if best.is_none_or(|b| cost < b.0) {
                    best = Some((cost, axis, i));
                }
            }
        }
        let (cost, axis, plane) = best?;
        if cost >= count as f32 && count <= 4 * BVH_LEAF_FACES {
            return None;
        }
        let (mut i, mut j) = (start, end);
        while i < j {
            if bin_of(self.centroids[self.order[i] as usize], axis) < plane {
                i += 1;
            } else {
                j -= 1;
                self.order.swap(i, j);
            }
        }
        Some(i)
    }
}
