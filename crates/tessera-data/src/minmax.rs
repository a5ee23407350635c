//! Min-max grid over blocks of cells and its octree (the max-reduced mip chain), used to skip
//! empty space: a node whose [min, max] excludes the isovalue holds no surface.

use crate::volume::Volume;

/// Cells per block along x, y, z (DESIGN §4: 8×8×4 = 256 cells, one GPU workgroup per block).
pub const BLOCK_CELLS: [u32; 3] = [8, 8, 4];

/// One level of the octree; level 0 has one node per block.
#[derive(Debug, Clone, PartialEq)]
pub struct MinMaxLevel {
    pub dims: [u32; 3],
    /// (min, max) of the sample values touching each node, x fastest.
    pub nodes: Vec<[f32; 2]>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct MinMaxOctree {
    pub levels: Vec<MinMaxLevel>,
}

/// Node counts per axis for every level, from blocks up to a single root.
pub fn level_dims(volume_dims: [u32; 3]) -> Vec<[u32; 3]> {
    let mut dims = [0, 1, 2].map(|a| (volume_dims[a].max(2) - 1).div_ceil(BLOCK_CELLS[a]));
    let mut out = vec![dims];
    while dims.iter().any(|&d| d > 1) {
        dims = dims.map(|d| d.div_ceil(2));
        out.push(dims);
    }
    out
}

/// Cells covered by node `node` of `level` along each axis: [lo, hi) in cell indices.
pub fn node_cells(volume_dims: [u32; 3], level: usize, node: [u32; 3]) -> [[u32; 2]; 3] {
    [0, 1, 2].map(|a| {
        let size = BLOCK_CELLS[a] << level;
        let cells = volume_dims[a] - 1;
        [
            (node[a] * size).min(cells),
            ((node[a] + 1) * size).min(cells),
        ]
    })
}

impl MinMaxOctree {
    pub fn build(volume: &Volume) -> MinMaxOctree {
        let vd = volume.dims();
        let all = level_dims(vd);
        let d0 = all[0];
        let mut nodes = Vec::with_capacity((d0[0] * d0[1] * d0[2]) as usize);
        for bz in 0..d0[2] {
            for by in 0..d0[1] {
                for bx in 0..d0[0] {
                    let c = node_cells(vd, 0, [bx, by, bz]);
                    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
                    // A block's cells touch samples c.lo ..= c.hi on each axis.
                    for z in c[2][0]..=c[2][1] {
                        for y in c[1][0]..=c[1][1] {
                            for x in c[0][0]..=c[0][1] {
                                let v = volume.texel(x, y, z);
                                lo = lo.min(v);
                                hi = hi.max(v);
                            }
                        }
                    }
                    nodes.push([lo, hi]);
                }
            }
        }
        let mut levels = vec![MinMaxLevel { dims: d0, nodes }];
        for &dims in &all[1..] {
            let child = levels.last().cloned().unwrap_or(MinMaxLevel {
                dims,
                nodes: vec![],
            });
            let mut nodes = Vec::with_capacity((dims[0] * dims[1] * dims[2]) as usize);
            for z in 0..dims[2] {
                for y in 0..dims[1] {
                    for x in 0..dims[0] {
                        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
                        for c in 0..8u32 {
                            let p = [2 * x + (c & 1), 2 * y + ((c >> 1) & 1), 2 * z + (c >> 2)];
                            if (0..3).all(|a| p[a] < child.dims[a]) {
                                let i =
                                    (p[0] + child.dims[0] * (p[1] + child.dims[1] * p[2])) as usize;
                                lo = lo.min(child.nodes[i][0]);
                                hi = hi.max(child.nodes[i][1]);
                            }
                        }
                        nodes.push([lo, hi]);
                    }
                }
            }
            levels.push(MinMaxLevel { dims, nodes });
        }
        MinMaxOctree { levels }
    }

    /// All levels' nodes in one array, level 0 first, as the GPU stores them.
    pub fn flattened(&self) -> Vec<[f32; 2]> {
        self.levels
            .iter()
            .flat_map(|l| l.nodes.iter().copied())
            .collect()
    }

    /// Fraction of blocks that may hold the surface at `iso`.
    pub fn occupied_fraction(&self, iso: f32) -> f64 {
        let blocks = self.levels[0].nodes.len();
        self.occupied_blocks(iso).count() as f64 / blocks.max(1) as f64
    }

    /// Block coordinates (level-0 nodes, x fastest) whose range holds `iso`, so that may
    /// hold surface. Conservative: a block whose minimum is exactly `iso` has no sample below
    /// it and no crossing.
    pub fn occupied_blocks(&self, iso: f32) -> impl Iterator<Item = [u32; 3]> + '_ {
        let l0 = &self.levels[0];
        let [nx, ny, _] = l0.dims;
        l0.nodes
            .iter()
            .enumerate()
            .filter(move |(_, n)| n[0] <= iso && iso <= n[1])
            .map(move |(i, _)| {
                let i = i as u32;
                [i % nx, i / nx % ny, i / (nx * ny)]
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::Samples;

    #[test]
    fn levels_reduce_to_one_root() {
        let dims = level_dims([257, 129, 65]);
        assert_eq!(dims[0], [32, 16, 16]);
        assert_eq!(*dims.last().unwrap(), [1, 1, 1]);
    }

    #[test]
    fn root_holds_the_volume_range_and_blocks_their_own() {
        let dims = [20u32, 11, 9];
        let n = (dims[0] * dims[1] * dims[2]) as usize;
        let samples: Vec<f32> = (0..n).map(|i| ((i * 7919) % 1000) as f32).collect();
        let v = Volume::new("t", dims, [1.0; 3], Samples::F32(samples.clone())).unwrap();
        let o = MinMaxOctree::build(&v);
        let root = o.levels.last().unwrap().nodes[0];
        let lo = samples.iter().cloned().fold(f32::INFINITY, f32::min);
        let hi = samples.iter().cloned().fold(f32::NEG_INFINITY, f32::max);
        assert_eq!(root, [lo, hi]);
        // Block (1,0,0) covers cells 8..16 → samples 8..=16 in x, 0..=8 in y, 0..=4 in z.
        let b = o.levels[0].nodes[1];
        let mut want = [f32::INFINITY, f32::NEG_INFINITY];
        for z in 0..=4 {
            for y in 0..=8 {
                for x in 8..=16 {
                    let s = v.texel(x, y, z);
                    want = [want[0].min(s), want[1].max(s)];
                }
            }
        }
        assert_eq!(b, want);
    }
}
