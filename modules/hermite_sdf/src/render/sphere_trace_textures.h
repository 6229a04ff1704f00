#pragma once
// The GPU side of the sphere-tracing baselines' fields: texel packing of a dense field into a 3D
// texture, and where the shaders find those textures (descriptor set 1, binding 0) -- a bindless
// table where the device has descriptor indexing, one descriptor set per texture where it has not
// (lavapipe), behind one interface.
#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "hermite_sdf/core/field.h"

namespace engine::gpu {
class Context;
}

namespace hsdf {

enum class TraceMethod : std::uint32_t {
  Trilinear = 0,  // f only, hardware trilinear filtering
  Hermite = 1,    // (f, fx, fy, fz), manual tricubic evaluation
};
inline constexpr std::uint32_t kTraceMethodCount = 2;

// A field's samples as texels, x fastest, then y, then z (Vulkan's buffer-to-image order), so
// texel (i,j,k) holds sample (i,j,k).
struct FieldTexels {
  VkFormat format = VK_FORMAT_UNDEFINED;
  std::vector<std::uint8_t> bytes;
};

// Trilinear: R32_SFLOAT (R16_SFLOAT when halfPrecision) of f. Hermite: R32G32B32A32_SFLOAT
// (R16G16B16A16_SFLOAT) of (f, fx, fy, fz). Error when the samples do not match the grid.
engine::Expected<FieldTexels> packFieldTexels(const HermiteField& field, TraceMethod method, bool halfPrecision);

VkFormat fieldTextureFormat(TraceMethod method, bool halfPrecision);

// Checks that the device can sample every field format from a 3D image (and filter the trilinear
// ones linearly); the error names the format that is missing a feature.
engine::Status checkFieldFormats(const engine::gpu::Context& context);

class FieldTextureBindings {
 public:
  static engine::Expected<std::unique_ptr<FieldTextureBindings>> create(const engine::gpu::Context& context,
                                                                       bool bindless);
  virtual ~FieldTextureBindings() = default;

  virtual bool bindless() const = 0;
  virtual VkDescriptorSetLayout layout() const = 0;
  // Makes a texture reachable by the shaders and returns its slot (SphereTraceDraw::texture).
  // The bindless table is one set that submitted frames have bound, so adding waits for the GPU
  // to go idle first (uploads are rare: once per asset and method).
  virtual engine::Expected<std::uint32_t> add(VkImageView view, VkSampler sampler) = 0;
  // Releases a slot once no frame in flight may draw with it (its texture was retired through the
  // frame's DeferredRelease and the frames that drew it have completed): never waits for the GPU.
  virtual void remove(std::uint32_t slot) = 0;
  // Binds set 1 for drawing the texture in `slot`: the whole table when bindless (bind once, the
  // slot is ignored), the slot's own set otherwise (bind per draw).
  virtual void bind(VkCommandBuffer cmd, VkPipelineLayout layout, std::uint32_t slot) const = 0;
};

}  // namespace hsdf
