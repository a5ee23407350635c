//! The block shapes a PMB extraction may use (paper C compares these four, around Liu et al.'s
//! best 8×4×4) and the most vertices one block can hold.

/// Cells per block along x, y and z, fixed when the extraction's pipelines are built.
/// 8×8×4 is the default where a size is not named.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum PmbBlockSize {
    B444,
    B844,
    #[default]
    B884,
    B888,
}

impl PmbBlockSize {
    pub const ALL: [PmbBlockSize; 4] = [
        PmbBlockSize::B444,
        PmbBlockSize::B844,
        PmbBlockSize::B884,
        PmbBlockSize::B888,
    ];

    pub const fn cells(self) -> [u32; 3] {
        match self {
            PmbBlockSize::B444 => [4, 4, 4],
            PmbBlockSize::B844 => [8, 4, 4],
            PmbBlockSize::B884 => [8, 8, 4],
            PmbBlockSize::B888 => [8, 8, 8],
        }
    }

    /// Samples of the block's closed box: its cells plus one layer beyond the max faces,
    /// where the padding cells that own the far faces' edges sit.
    pub const fn box_points(self) -> u32 {
        let [x, y, z] = self.cells();
        (x + 1) * (y + 1) * (z + 1)
    }

    /// The most vertices a block can have: every edge of its box crossed (three per sample is
    /// an upper bound). Below 2^16 for every size, so local indices fit 16 bits.
    pub const fn max_vertices(self) -> u32 {
        3 * self.box_points()
    }

    /// Blocks per axis covering the cells of a volume of `dims` samples (partial blocks at
    /// the far faces included).
    pub fn grid(self, dims: [u32; 3]) -> [u32; 3] {
        let cells = self.cells();
        std::array::from_fn(|a| dims[a].saturating_sub(1).div_ceil(cells[a]))
    }

    /// The size named `text` (a [`PmbBlockSize::name`], e.g. `"8x8x4"`).
    pub fn parse(text: &str) -> crate::error::Result<PmbBlockSize> {
        PmbBlockSize::ALL
            .into_iter()
            .find(|s| s.name() == text)
            .ok_or_else(|| {
                crate::error::DataError::Invalid(format!(
                    "PMB block size '{text}': choose {}",
                    PmbBlockSize::ALL.map(|s| s.name()).join(", ")
                ))
            })
    }

    /// A short name, e.g. `"8x4x4"`.
    pub fn name(self) -> String {
        let [x, y, z] = self.cells();
        format!("{x}x{y}x{z}")
    }
}

const _: () = {
    let mut i = 0;
    while i < PmbBlockSize::ALL.len() {
        assert!(
            PmbBlockSize::ALL[i].max_vertices() <= 1 << 16,
            "local indices of every block size fit 16 bits"
        );
        i += 1;
    }
};
