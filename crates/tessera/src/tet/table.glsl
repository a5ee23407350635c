// Integrand tables as tessera_data::transfer::IntegrandTable::gpu_words lays them out: from
// `base` in the includer's `table` buffer, TABLE_KNOTS values linear between uniformly spaced
// knots over [0, 1], then their running integral in knot units. A buffer may hold several
// tables back to back (2 * TABLE_KNOTS entries each), so the tet techniques share these
// integrals whatever optical model they combine them into.

// The table at u (knot units) within knot interval i (i <= u <= i + 1).
vec3 table_in_interval(uint base, uint i, float u) {
    return mix(table[base + i].rgb, table[base + i + 1u].rgb, u - float(i));
}

vec3 table_value_at(uint base, float x) {
    float u = clamp(x, 0.0, 1.0) * float(TABLE_KNOTS - 1);
    return table_in_interval(base, min(uint(u), uint(TABLE_KNOTS - 2)), u);
}

// Mean of the table over the scalars between a and b (clamped to [0, 1]). Where lo and hi
// share a knot interval the table is linear between them: its value midway. Otherwise the
// integral by trapezoids in three pieces, lo to the end of its interval, the whole intervals
// between (from the running integral), the start of hi's interval to hi, over the stretch.
// Both are evaluated and one chosen by selection, so that the invocations of a subgroup whose
// stretches cross knots and those whose stretches do not stay together: on the 944 k-tet
// box's scalar field (docs/BENCHMARKS.md, runs 97-98) a branch between them took 3.5 % longer
// far, and the trapezoids written with the knots' values (two interpolations a piece) 3 %.
vec3 table_mean_at(uint base, float a, float b) {
    float last = float(TABLE_KNOTS - 1);
    float lo = clamp(min(a, b), 0.0, 1.0) * last;
    float hi = clamp(max(a, b), 0.0, 1.0) * last;
    uint i = min(uint(lo), uint(TABLE_KNOTS - 2));
    uint j = min(uint(hi), uint(TABLE_KNOTS - 2));
    // lo and hi within their intervals, in knot units.
    float lo_in = lo - float(i);
    float hi_in = hi - float(j);
    vec3 value_i = table[base + i].rgb;
    vec3 slope_i = table[base + i + 1u].rgb - value_i;
    vec3 value_j = table[base + j].rgb;
    vec3 slope_j = table[base + j + 1u].rgb - value_j;
    uint running = base + uint(TABLE_KNOTS);
    vec3 head = (value_i + slope_i * (0.5 * (1.0 + lo_in))) * (1.0 - lo_in);
    vec3 whole = table[running + j].rgb - table[running + i + 1u].rgb;
    vec3 tail = (value_j + slope_j * (0.5 * hi_in)) * hi_in;
    vec3 midway = table_in_interval(base, i, 0.5 * (lo + hi));
    return i == j ? midway : (head + whole + tail) / (hi - lo);
}
