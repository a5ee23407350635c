// What every compute pass that evaluates tets at pixels includes (the per-tet, tile, binned
// counting and binned shading passes): the technique's buffers and parameters, the proxies,
// the integrands and how a pixel's value is combined and stored. The includer enables the
// extensions first (float atomics; with INTEGRAND_SDF, 64-bit integer atomics).

#include "tet/interval/buffers.glsl"
#include "tet/interval/params.glsl"
#include "tet/interval/compute_buffers.glsl"
#include "tet/interval/proxy.glsl"
#include "tet/interval/length.glsl"
#include "tet/interval/table.glsl"
#include "tet/interval/integrand.glsl"
#if INTEGRAND == INTEGRAND_SDF
#include "tet/interval/sdf.glsl"
#endif
#include "tet/interval/pixel_value.glsl"
#include "tet/interval/splat.glsl"
