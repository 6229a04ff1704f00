#pragma once
// What may legitimately differ between Vulkan devices, written down once per kind of comparison a
// GPU test makes. Each tolerance says which device difference it covers; where the difference
// depends on the device, it is computed from what the device reports (Context::capabilities(),
// the physical device's limits), never loosened for lavapipe: on lavapipe every value is the one
// the tests used before the suite ran on other devices.
//
// Device differences that matter here (docs/gpu-vs-lavapipe.md has the review of every shader):
// - Texture filtering: lavapipe filters in full float; hardware quantizes the trilinear weights to
//   subTexelPrecisionBits fractional bits (8 on lavapipe's report and on NVIDIA), so a filtered
//   value may be off by 2^-(bits+1) of the difference between two neighbouring texels. For a
//   distance field in grid units (neighbours differ by at most ~1 cell) that moves the filtered
//   surface by up to 2^-(bits+1) cells / cos(angle between ray and normal).
// - texelFetch + float arithmetic (dense Hermite tracer, cells): the same texels everywhere; only
//   the compiler's choice of fused multiply-add and evaluation order differs (~1e-7 relative), far
//   inside the tracer's own stop tolerance (epsilon = 1e-4 cells).
// - Rasterization: every Vulkan device samples coverage at the pixel centre with the top-left rule
//   and subPixelPrecisionBits of vertex snapping (8 on lavapipe and NVIDIA); only pixels on an edge
//   may go either way, so tests skip edge pixels or count them.
// - fp16 textures: the host rounds to half (hsdf::floatToHalf) and every device reads R16/RGBA16F
//   exactly, so the reference of the rounded field holds on any device with no extra tolerance.
#include <cstdint>

#include <vulkan/vulkan.h>

#include "engine/gpu/context.h"

namespace gputest {

struct DeviceTolerances {
  // Sphere tracing stops when |f| < epsilon * h (epsilon = 1e-4 cells): the stop lies up to
  // ~eps / (|grad F| cos) cells before the root. 4 * eps covers |grad F| >= 1/4 (the test shapes'
  // fields near their surfaces). Same on every device: the stop test is plain float arithmetic.
  double traceStopCells = 4.0 * 1e-4;
  // The trilinear filter's weight quantization (see above): 2^-(subTexelPrecisionBits + 1) cells.
  // lavapipe reports 8 bits (and filters in float, so it needs less): 1/512 there, as before.
  double trilinearFilterCells = 1.0 / 512.0;
  // render_test.cpp: mesh depth at a pixel centre against the depth computed on the CPU (reverse-Z,
  // D32_SFLOAT): the rasterizer interpolates the plane in fp32, a few ulp of values ~0.01-1 on any
  // device.
  double meshDepthAbsolute = 1e-6;
  // gltf_scene_test.cpp: a triangle mesh against the CPU ray cast of the same triangles. Coverage
  // may differ only on the silhouette (pixel-centre sampling with the top-left rule and 8-bit
  // vertex snapping on lavapipe and GPUs alike: an edge through a pixel centre goes either way),
  // at most this share of the covered pixels; interior depth within fp32 interpolation; at the
  // silhouette the rasterizer may take the neighbouring triangle of the one the cast hits.
  double meshSilhouetteCoverageShare = 1.0 / 50.0;
  double meshInteriorRelativeDepth = 2e-3;
  double meshSilhouetteRelativeDepth = 5e-2;
  // adversarial_fields_test.cpp: every method on zero gradients, 1e30 values, a tangent surface,
  // rays along cell edges. Near a tangent the depth of a float search is ill-conditioned on any
  // device (a 1-ulp change of F moves the root far), hence a wider share and depth than the
  // smooth shapes get; the trilinear filter's quantization (below, <= 2^-9 cells) fits inside.
  double adversarialCoverageDisagreement = 1e-2;
  double adversarialInteriorDepthP99Cells = 1e-2;
  // Share of pixels whose coverage may differ between a GPU frame and the CPU reference of the
  // same interpolant: silhouette pixels where a float search and the double reference go either
  // way (grazing rays), on any device.
  double coverageDisagreement = 1e-3;
  // The bindless and per-texture-set sphere-tracing paths on one device: the same tracing code
  // reading the same texels, compiled as two shader variants. They agree exactly except where the
  // compiler contracts a different multiply-add, which can move a grazing silhouette pixel or the
  // last bits of a depth: at most this share of pixels, and this relative depth difference.
  double samePathCoverage = 5e-4;
  double samePathDepthRelative = 1e-5;
  // Whether the fragments of one pixel are shaded one primitive after the other, each seeing the
  // depth (and buffer writes) of those before it: lavapipe shades in primitive order; a GPU shades
  // overlapping fragments in parallel (an H200 did the same root-search work with and without the
  // cells' early depth stage). Work-saving claims that rest on that order hold only where it is true.
  bool fragmentsShadeInPrimitiveOrder = true;

  // The depth tolerance of a sphere tracer against its reference, in cells along the ray (divide
  // by cos(angle between ray and normal) per pixel): trilinear adds the filter's quantization.
  double traceDepthCells(bool trilinear) const {
    return trilinear ? traceStopCells + trilinearFilterCells : traceStopCells;
  }
};

// The tolerances for the device `context` runs on.
inline DeviceTolerances tolerancesFor(const engine::gpu::Context& context) {
  DeviceTolerances t;
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(context.physicalDevice(), &properties);
  // Never below lavapipe's 1/512: a device that claims more bits still gets the tolerance the
  // tests always had; one with fewer bits (coarser weights) gets a wider one.
  const std::uint32_t bits = properties.limits.subTexelPrecisionBits;
  const double quantization = bits >= 8 ? 1.0 / 512.0 : 1.0 / double(2u << bits);
  t.trilinearFilterCells = context.capabilities().isSoftwareRasterizer ? 1.0 / 512.0 : quantization;
  t.fragmentsShadeInPrimitiveOrder = context.capabilities().isSoftwareRasterizer;
  return t;
}

}  // namespace gputest
