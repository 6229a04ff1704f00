// How far a proxy box (a cell or a run of cells) is grown beyond the cells it covers (cells.vert,
// runs.vert), and how far the fragment shaders search beyond it (cells_depth.glsl, runs_depth.glsl).
#ifndef HSDF_PROXY_DILATION_GLSL
#define HSDF_PROXY_DILATION_GLSL

// The proxy is the cell's box dilated by `dilation` cells on every side, so that a ray which meets
// the cell is rasterized by its proxy even where the cell's edge is a silhouette of the drawn cells
// (the neighbour dropped as empty): the rasterizer snaps vertices to 1/256 pixel, and a pixel
// centre that close to the edge could fall outside the box's triangles while its ray meets the box.
// 0.02 pixel at the cell's centre is 5x the snapping; the fragment shader searches the ray over
// the same dilated box (docs/root-finding.md).
const float kDilationPixels = CELL_DILATION_PIXELS;
const float kMinDilation = CELL_MIN_DILATION;

// The dilation in cells of a cell whose centre has clip w `clipW` (its view depth in front of a
// perspective eye; 1 for an orthographic camera, whose pixels span the same at every depth), in an
// object whose smallest scale (the most cells per world unit, along its most shrunk direction) is
// `minScale`.
float proxyDilationAt(FrameGlobals frame, float clipW, float h, float minScale) {
  float worldPerPixel = 2.0 * max(clipW, 0.0) / (frame.proj[1][1] * frame.viewport.y);
  return max(kMinDilation, kDilationPixels * worldPerPixel / (h * minScale));
}

// The object's smallest scale: its model matrix's smallest singular value, made on the host
// (hermite_host_device.h, after CELL_MIN_DILATION). Its shortest column overstates it under a
// shear: 45x for two unit columns at cos 0.9995, and the dilation shrank below the snapping.
float objectMinScale(ObjectData object) {
  return object.material.z;
}

float proxyDilation(FrameGlobals frame, ObjectData object, vec3 cellCentre, float h) {
  vec4 view = frame.view * (object.model * vec4(cellCentre, 1.0));
  float clipW = frame.proj[2][3] * view.z + frame.proj[3][3];  // -z (perspective) or 1 (orthographic)
  return proxyDilationAt(frame, clipW, h, objectMinScale(object));
}

#endif
