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

// Mean of the table over the scalars between a and b (clamped to [0, 1]): the integral by
// trapezoids in three pieces, lo to the end of its knot interval, the whole intervals between
// (from the running integral), the start of hi's interval to hi; where lo and hi share an
// interval, the first piece runs to hi and the others are empty. Every piece is evaluated and
// the pieces chosen by selection, so that the invocations of a subgroup whose stretches cross
// knots and those whose stretches do not stay together.
vec3 table_mean_at(uint base, float a, float b) {
    float last = float(TABLE_KNOTS - 1);
    float lo = clamp(min(a, b), 0.0, 1.0) * last;
    float hi = clamp(max(a, b), 0.0, 1.0) * last;
    uint i = min(uint(lo), uint(TABLE_KNOTS - 2));
    uint j = min(uint(hi), uint(TABLE_KNOTS - 2));
    bool one_interval = i == j;
    float first_end = one_interval ? hi : float(i + 1u);
    float last_start = one_interval ? hi : float(j);
    uint running = base + uint(TABLE_KNOTS);
    vec3 head = (table_in_interval(base, i, lo) + table_in_interval(base, i, first_end)) * (0.5 * (first_end - lo));
    vec3 whole = one_interval ? vec3(0.0) : table[running + j].rgb - table[running + i + 1u].rgb;
    vec3 tail = (table_in_interval(base, j, last_start) + table_in_interval(base, j, hi)) * (0.5 * (hi - last_start));
    float extent = hi - lo;
    // A stretch of one scalar: the table's value there.
    return extent > 0.0 ? (head + whole + tail) / extent : table_in_interval(base, i, lo);
}
