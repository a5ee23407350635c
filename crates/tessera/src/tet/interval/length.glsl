// The world-space length of a pixel ray inside a tet, from interval shading's interpolated
// attributes. Needs tet/interval/params.glsl.

// 1/z of the proxy's second face, from the first's and their difference.
float second_inverse_depth(vec4 attrs) {
    return attrs.x - attrs.y;
}

// World-space length of the pixel ray between the two faces: the view-depth difference
// 1/b - 1/a = (a - b) / (a b) from the interpolated difference, without cancellation.
float interval_length(vec4 attrs, vec2 ndc) {
    float depth = abs(attrs.y) / (attrs.x * second_inverse_depth(attrs));
    // The view-space ray through the pixel has forward component 1; its length turns a depth
    // difference into a distance.
    vec2 slope = vec2(ndc.x * params.tan_half_fov.x, -ndc.y * params.tan_half_fov.y);
    return depth * sqrt(1.0 + dot(slope, slope));
}
