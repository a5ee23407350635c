// The world-space length of a pixel ray inside a tet, from interval shading's interpolated
// inverse view depths. Needs tet/interval/params.glsl.

// World-space length of the pixel ray between the faces whose inverse view depths are given.
float interval_length(vec2 inverse_depths, vec2 ndc) {
    float front = 1.0 / inverse_depths.x;
    float back = 1.0 / inverse_depths.y;
    // The view-space ray through the pixel has forward component 1; its length turns a depth
    // difference into a distance.
    vec2 slope = vec2(ndc.x * params.view.x, -ndc.y * params.view.y);
    return abs(back - front) * sqrt(1.0 + dot(slope, slope));
}
