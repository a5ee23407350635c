// The integrand table (`table`: TABLE_KNOTS values linear between uniformly spaced knots over
// [0, 1], then their running integral in knot units) and integrals over it.

#if INTEGRAND != INTEGRAND_TET_ABSORPTION
vec3 table_value(float x) {
    float u = clamp(x, 0.0, 1.0) * float(TABLE_KNOTS - 1);
    uint i = min(uint(u), uint(TABLE_KNOTS - 2));
    return mix(table[i].rgb, table[i + 1u].rgb, u - float(i));
}

// Integral of the table from knot i to u (in knot units, i <= u <= i + 1).
vec3 table_partial(uint i, float u) {
    float d = u - float(i);
    return d * (table[i].rgb + mix(table[i].rgb, table[i + 1u].rgb, d)) * 0.5;
}

vec3 table_mean(float a, float b) {
    float last = float(TABLE_KNOTS - 1);
    float lo = clamp(min(a, b), 0.0, 1.0) * last;
    float hi = clamp(max(a, b), 0.0, 1.0) * last;
    uint i = min(uint(lo), uint(TABLE_KNOTS - 2));
    uint j = min(uint(hi), uint(TABLE_KNOTS - 2));
    if (i == j) {
        // Within one knot interval the table is linear: its mean is the middle value.
        return table_value(0.5 * (lo + hi) / last);
    }
    // The tail of interval i, whole intervals i+1 .. j-1 from the running integral, the head of j.
    vec3 whole = table[TABLE_KNOTS + j].rgb - table[TABLE_KNOTS + i + 1u].rgb;
    vec3 sum = table_partial(i, float(i + 1u)) - table_partial(i, lo) + whole + table_partial(j, hi);
    return sum / (hi - lo);
}
#endif
