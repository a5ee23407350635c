//! Ready-made scenes of paper E's benchmarks (the knit curtain and a seashell) live with the
//! data (`tessera_data::param::scenes`); re-exported here beside the techniques that draw them.

pub use tessera_data::param::scenes::*;
