// Integrand tables as tessera_data::transfer::IntegrandTable::gpu_words lays them out: from
// `base` in the includer's `table` buffer, TABLE_KNOTS values linear between uniformly spaced
// knots over [0, 1], then their running integral in knot units. A buffer may hold several
// tables back to back (2 * TABLE_KNOTS entries each), so the tet techniques share these
// integrals whatever optical model they combine them into.

vec3 table_value_at(uint base, float x) {
    float u = clamp(x, 0.0, 1.0) * float(TABLE_KNOTS - 1);
    uint i = min(uint(u), uint(TABLE_KNOTS - 2));
    return mix(table[base + i].rgb, table[base + i + 1u].rgb, u - float(i));
}

// Integral of the table from knot i to u (in knot units, i <= u <= i + 1).
vec3 table_partial_at(uint base, uint i, float u) {
    float d = u - float(i);
    return d * (table[base + i].rgb + mix(table[base + i].rgb, table[base + i + 1u].rgb, d)) * 0.5;
}

// Mean of the table over the scalars between a and b (clamped to [0, 1]).
vec3 table_mean_at(uint base, float a, float b) {
    float last = float(TABLE_KNOTS - 1);
    float lo = clamp(min(a, b), 0.0, 1.0) * last;
    float hi = clamp(max(a, b), 0.0, 1.0) * last;
    uint i = min(uint(lo), uint(TABLE_KNOTS - 2));
    uint j = min(uint(hi), uint(TABLE_KNOTS - 2));
    if (i == j) {
        // Within one knot interval the table is linear: its mean is the middle value.
        return table_value_at(base, 0.5 * (lo + hi) / last);
    }
    // The tail of interval i, whole intervals i+1 .. j-1 from the running integral, the head of j.
    uint running = base + uint(TABLE_KNOTS);
    vec3 whole = table[running + j].rgb - table[running + i + 1u].rgb;
    vec3 sum = table_partial_at(base, i, float(i + 1u)) - table_partial_at(base, i, lo) + whole
        + table_partial_at(base, j, hi);
    return sum / (hi - lo);
}
