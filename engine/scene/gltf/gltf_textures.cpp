// glTF textures (gltf_textures.h): sampler, image source, decoding.
#include "engine/scene/gltf/gltf_textures.h"

#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/core/image_io.h"

namespace engine::scene::gltf {
namespace {

// glTF sampler enums (OpenGL's numbers).
constexpr int kNearest = 9728;
constexpr int kLinear = 9729;
constexpr int kNearestMipmapNearest = 9984;
constexpr int kLinearMipmapNearest = 9985;
constexpr int kNearestMipmapLinear = 9986;
constexpr int kLinearMipmapLinear = 9987;
constexpr int kClampToEdge = 33071;
constexpr int kMirroredRepeat = 33648;

TextureWrap wrapOf(int wrap) {
  if (wrap == kClampToEdge) return TextureWrap::ClampToEdge;
  if (wrap == kMirroredRepeat) return TextureWrap::MirroredRepeat;
  return TextureWrap::Repeat;  // 10497, and the default
}

// A sampler's filters and wraps into `out`. An absent minFilter or magFilter leaves the choice to the
// renderer: linear, and trilinear between mipmaps.
void applySampler(const tinygltf::Sampler& sampler, TextureData& out) {
  out.magFilter = sampler.magFilter == kNearest ? TextureFilter::Nearest : TextureFilter::Linear;
  const int min = sampler.minFilter;
  if (min == kNearest || min == kLinear) {
    out.mipmaps = false;
    out.minFilter = min == kNearest ? TextureFilter::Nearest : TextureFilter::Linear;
  } else if (min >= kNearestMipmapNearest && min <= kLinearMipmapLinear) {
    out.minFilter = (min == kNearestMipmapNearest || min == kNearestMipmapLinear) ? TextureFilter::Nearest
                                                                                  : TextureFilter::Linear;
    out.mipmapFilter = (min == kNearestMipmapNearest || min == kLinearMipmapNearest) ? TextureFilter::Nearest
                                                                                    : TextureFilter::Linear;
  }
  out.wrapS = wrapOf(sampler.wrapS);
  out.wrapT = wrapOf(sampler.wrapT);
}

// The encoded bytes of an image: its bufferView's, a data: URI's, or a file's beside the .gltf.
Expected<std::vector<std::uint8_t>> encodedImage(ImportContext& context, const ImageSource& image) {
  if (image.bufferView >= 0) {
    ENGINE_TRY_ASSIGN(const auto bytes, bufferViewBytes(context, image.bufferView));
    return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
  }
  if (image.uri.empty()) return makeError("has neither a uri nor a bufferView");
  if (tinygltf::IsDataURI(image.uri)) {
    std::vector<unsigned char> bytes;
    std::string mime;
    if (!tinygltf::DecodeDataURI(&bytes, mime, image.uri, 0, false)) return makeError("its data: URI cannot be decoded");
    return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
  }
  if (!context.files) return makeError(fmt::format("external file '{}' not allowed here", image.uri));
  return readFileBesideGltf(*context.files, image.uri);
}

}  // namespace

Expected<TextureData> convertTexture(ImportContext& context, int textureIndex) {
  const auto& model = context.model;
  if (!inRange(textureIndex, model.textures))
    return makeError(describeIndexRange("texture", textureIndex, model.textures.size()));
  const tinygltf::Texture& texture = model.textures[std::size_t(textureIndex)];
  const std::string where = fmt::format("texture {}", textureIndex);
  TextureData out;
  if (texture.sampler != -1) {
    if (!inRange(texture.sampler, model.samplers))
      return makeError(fmt::format("{}: {}", where, describeIndexRange("sampler", texture.sampler, model.samplers.size())));
    applySampler(model.samplers[std::size_t(texture.sampler)], out);
  }
  const auto& images = context.plan.images;
  if (!inRange(texture.source, images))
    return makeError(fmt::format("{}: {}", where, describeIndexRange("image", texture.source, images.size())));
  const ImageSource& image = images[std::size_t(texture.source)];
  out.name = image.name.empty() ? fmt::format("image {}", texture.source) : image.name;
  const std::string imageWhere = fmt::format("{}: image {} '{}'", where, texture.source, out.name);
  ENGINE_TRY_ASSIGN(const auto encoded, encodedImage(context, image).withContext(imageWhere));
  ENGINE_TRY_ASSIGN(LoadedImage decoded, decodeImage(encoded, kMaxTextureSide).withContext(imageWhere));
  ENGINE_TRY(chargeDecode(context, decoded.rgba.size()).withContext(imageWhere));
  out.width = decoded.width;
  out.height = decoded.height;
  out.rgba = std::move(decoded.rgba);
  return out;
}

}  // namespace engine::scene::gltf
