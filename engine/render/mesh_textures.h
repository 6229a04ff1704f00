#pragma once
// The textures of mesh materials (glTF baseColorTexture, metallicRoughnessTexture, occlusionTexture,
// emissiveTexture, normalTexture): RGBA8 images with their mip chains and samplers, and one descriptor set per
// material holding one image per texture kind (mesh.frag's set 0, bindings MESH_TEXTURE_*). A set per
// material, not a bindless table: devices without descriptor indexing (lavapipe) draw them too, and
// the mesh feature binds a material's set once per batch of the meshes that use it. Image 0 is one
// white texel, which every kind a material lacks samples: its factor times 1.0 is the factor the
// material had before textures were drawn (glTF's defaults: no occlusion, the emissiveFactor alone;
// a normal texture is only read with a scale other than 0, MeshRenderable::normalScale).
// Set 0 holds it in every binding (a mesh without textures).
#include <array>
#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/gpu/device_handle.h"
#include "engine/gpu/image.h"
#include "engine/gpu/image_sampler_sets.h"
#include "engine/render/components.h"
#include "engine/scene/scene_data.h"
#include "shared/host_device.h"

namespace engine::gpu {
class Context;
}

namespace engine::render {

// An image uploaded into MeshTextures (MeshTextures::addImage); 0: the white texel.
struct MeshImageHandle {
  std::uint32_t index = 0;
};

// How an image's texels are read: colours (base colour, emission) are sRGB-encoded, data
// (metallic-roughness, occlusion) is linear.
enum class TexelEncoding { Srgb, Linear };

// The images of one material's set, one per texture kind (the white texel where it has none).
struct MaterialImages {
  MeshImageHandle baseColor;          // sRGB; rgb times the base colour, a times its alpha
  MeshImageHandle metallicRoughness;  // linear; g times the roughness, b times the metallic
  MeshImageHandle occlusion;          // linear; r: how much of the ambient light reaches the surface
  MeshImageHandle emissive;           // sRGB; rgb times the emission
  MeshImageHandle normal;             // linear; the normal in the tangent frame (read when the scale is not 0)
};

// One texture kind of a material: where a glTF material names its texture and MaterialImages its
// image, how its texels are read, and its binding in the material's set (MESH_TEXTURE_*).
struct MaterialTextureKind {
  int scene::MaterialData::*texture;
  MeshImageHandle MaterialImages::*image;
  TexelEncoding encoding;
  std::uint32_t binding;
};

// Every kind, the one list of them (the set's bindings, the uploads of scene_instantiate).
inline constexpr std::array<MaterialTextureKind, MESH_TEXTURE_COUNT> kMaterialTextureKinds = {{
    {&scene::MaterialData::baseColorTexture, &MaterialImages::baseColor, TexelEncoding::Srgb, MESH_TEXTURE_BASE_COLOR},
    {&scene::MaterialData::metallicRoughnessTexture, &MaterialImages::metallicRoughness, TexelEncoding::Linear,
     MESH_TEXTURE_METALLIC_ROUGHNESS},
    {&scene::MaterialData::occlusionTexture, &MaterialImages::occlusion, TexelEncoding::Linear, MESH_TEXTURE_OCCLUSION},
    {&scene::MaterialData::emissiveTexture, &MaterialImages::emissive, TexelEncoding::Srgb, MESH_TEXTURE_EMISSIVE},
    {&scene::MaterialData::normalTexture, &MaterialImages::normal, TexelEncoding::Linear, MESH_TEXTURE_NORMAL},
}};

class MeshTextures {
 public:
  explicit MeshTextures(const gpu::Context& context);
  ~MeshTextures() = default;
  MeshTextures(const MeshTextures&) = delete;
  MeshTextures& operator=(const MeshTextures&) = delete;

  // Uploads `texture` with its mip chain, its texels read as `encoding` says (waits for the GPU;
  // textures come at load). Throws VulkanError when the device refuses (checked-call convention).
  MeshImageHandle addImage(const scene::TextureData& texture, TexelEncoding encoding);
  // A material's set of `images` (an unknown handle reads the white texel). Throws VulkanError when
  // no pool gives a set.
  TextureHandle addMaterial(const MaterialImages& images);
  // Material sets, set 0 included.
  std::uint32_t count() const { return static_cast<std::uint32_t>(sets_.size()); }

  VkDescriptorSetLayout layout() const { return setAllocator_.layout(); }
  // Binds `textures`' set as set 0 of `layout` (set 0 for an unknown handle).
  void bind(VkCommandBuffer cmd, VkPipelineLayout layout, TextureHandle textures) const;

 private:
  struct Entry {
    gpu::Image image;
    gpu::SamplerHandle sampler;
  };

  const gpu::Context& context_;
  gpu::ImageSamplerSets setAllocator_;
  std::vector<Entry> images_;
  std::vector<VkDescriptorSet> sets_;  // live as long as the textures: freed with the sets' pools
};

}  // namespace engine::render
