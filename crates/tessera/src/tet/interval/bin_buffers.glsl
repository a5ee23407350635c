// The binned compute path's buffers after compute_buffers.glsl (host side: `TetBins`), and the
// grid of TILE × TILE-pixel screen tiles they sort tets into (tile = row × columns + column).
// Capacities are the bound buffers' lengths, so growing them builds no pipeline.
layout(binding = 9) buffer BinCount {
    uint bin_entry_count;  // entries reserved, including those that did not fit
    uint bin_dispatch[3];  // the scatter pass's indirect dispatch
};
// Per (tet, tile) it touches: the tet, and the tile (NO_TET where the reservation overflowed).
layout(binding = 10) buffer BinEntries { uvec2 bin_entries[]; };
// Per tile: its count of tets, then its exclusive prefix (the scan), then after the scatter
// where its list ends, which is where the next tile's starts.
layout(binding = 11) buffer TileBins { uint tile_bins[]; };
// The tets of every tile, tile after tile.
layout(binding = 12) buffer BinList { uint bin_list[]; };

// Columns and rows of screen tiles.
uvec2 bin_grid() {
    return (params.counts.yz + uint(TILE) - 1u) / uint(TILE);
}

// Whether the tile counters hold the screen's tiles (else every tet is drawn unbinned).
bool bins_hold_screen() {
    uvec2 grid = bin_grid();
    return grid.x * grid.y <= uint(tile_bins.length());
}
