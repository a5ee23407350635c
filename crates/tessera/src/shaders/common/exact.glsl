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

// sqrt(x) as the CPU rounds it (to nearest). Vulkan lets sqrt be off by a few ulp, so the
// root is corrected by the exact residual x - s^2 (Sterbenz's lemma): s + (x - s^2) / 2s differs
// from the true root by far less than an ulp's millionth, and one correctly rounded addition
// rounds it as the CPU does, short of roots within that distance of a rounding midpoint.
float rounded_sqrt(float x) {
    float s = sqrt(x);
    if (!(s > 0.0)) {
        return s;
    }
    precise float p = s * s;
    precise float residual = (x - p) - product_error(s, s, p);
    precise float root = s + residual / (2.0 * s);
    return root;
}

// a / b as the CPU rounds it (to nearest), by the same correction as rounded_sqrt: the
// residual a - bq is exact (Sterbenz; bq's rounding error added back), and q + residual / b
// is rounded once. Infinite, NaN and zero quotients are returned as the division gave them,
// as is any quotient whose correction would overflow.
float rounded_divide(float a, float b) {
    float q = a / b;
    if (isinf(q) || isnan(q) || q == 0.0) {
        return q;
    }
    precise float p = b * q;
    precise float residual = (a - p) - product_error(b, q, p);
    precise float corrected = q + residual / b;
    return isinf(corrected) || isnan(corrected) ? q : corrected;
}
