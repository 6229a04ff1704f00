// Colours of the debug views, shared by every renderer so that views compare across methods.
#ifndef HSDF_DEBUG_COLORS_GLSL
#define HSDF_DEBUG_COLORS_GLSL

// Heat map for DEBUG_VIEW_EVALS: 0 -> blue, 0.5 -> green, 1 -> red.
vec3 heat(float x) {
  x = clamp(x, 0.0, 1.0);
  return clamp(vec3(2.0 * x - 0.5, 1.0 - abs(2.0 * x - 1.0), 1.5 - 2.0 * x), 0.0, 1.0);
}

// A stable, well spread colour per integer triple (DEBUG_VIEW_CELLS).
vec3 hashColor(uvec3 key) {
  uint h = key.x * 73856093u ^ key.y * 19349663u ^ key.z * 83492791u;
  h = (h ^ (h >> 13)) * 0x5bd1e995u;
  return vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0 * 0.8 + 0.2;
}

#endif
