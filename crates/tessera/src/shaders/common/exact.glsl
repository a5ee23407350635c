// Exact arithmetic pieces shared by passes that must round as the CPU does.

// The rounding error of a * b = p (a * b == p + error exactly), by Dekker's product on
// Veltkamp halves: exact with plain IEEE arithmetic, where `precise` keeps the compiler from
// fusing or reassociating, so it needs no hardware fma (lavapipe's is not fused).
float product_error(float a, float b, float p) {
    precise float ca = 4097.0 * a;
    precise float a_hi = ca - (ca - a);
    precise float a_lo = a - a_hi;
    precise float cb = 4097.0 * b;
    precise float b_hi = cb - (cb - b);
    precise float b_lo = b - b_hi;
    precise float e = ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo;
    return e;
}
