// Interval shading's one integrand table, at the start of `table` (tet/table.glsl).

#if INTEGRAND != INTEGRAND_TET_ABSORPTION
#include "tet/table.glsl"

vec3 table_value(float x) {
    return table_value_at(0u, x);
}

vec3 table_mean(float a, float b) {
    return table_mean_at(0u, a, b);
}
#endif
