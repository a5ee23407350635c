#version 460
// Shell traces keep what they found in the payload; a ray that found nothing leaves it as the
// ray-generation shader set it.
#extension GL_EXT_ray_tracing : require
void main() {
}
