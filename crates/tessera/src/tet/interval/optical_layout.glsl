// Where the compute path keeps channel `channel` of a pixel's accumulation (host side:
// `OpticalTarget::read`): one plane per channel, each a word per pixel of the `pixels`, so that
// a tet's three channels at a pixel are three atomics far apart rather than into one 16-byte
// texel.
uint optical_index(uint pixel, uint channel, uint pixels) {
    return channel * pixels + pixel;
}
