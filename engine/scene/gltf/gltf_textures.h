#pragma once
// Internal to engine_scene (gltf_convert.cpp): a glTF texture -- its image decoded (PNG or JPEG, from
// a bufferView, a data: URI or a file beside the .gltf) and its sampler's filters and wrap modes --
// as TextureData. Every index is checked; a problem is an error naming it, which the conversion
// turns into a warning (the material is drawn in its factor), never a crash.
#include <cstdint>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/scene/gltf/gltf_accessors.h"
#include "engine/scene/scene_data.h"

namespace engine::scene::gltf {

// The largest side of an image that is decoded: 8192 texels (256 MiB of RGBA8), which holds the
// 4K and 8K textures of real scenes; a larger one is refused before a pixel is decoded.
inline constexpr std::uint32_t kMaxTextureSide = 8192;

// glTF textures[textureIndex] as TextureData; its decoded texels are charged to the decode budget.
Expected<TextureData> convertTexture(ImportContext& context, int textureIndex);

// Where a textureInfo reads its texture: the TEXCOORD set, and KHR_texture_transform's affine map
// (offset, rotation, scale) from the coordinates the primitive stores to those the texture is
// read at -- the identity without the extension.
struct TextureCoordinates {
  int set = 0;
  glm::mat3 transform{1.0f};
};

// The coordinates of a textureInfo (any kind: tinygltf has one type per material texture) of
// `texCoord` and `extensions`; the extension's texCoord overrides the textureInfo's. A malformed
// extension is an error naming the field.
Expected<TextureCoordinates> textureCoordinates(int texCoord, const tinygltf::ExtensionMap& extensions);

}  // namespace engine::scene::gltf
