// glTF textures (gltf_textures.h): sampler, image source, decoding.
#include "engine/scene/gltf/gltf_textures.h"

#include <cmath>
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
constexpr const char* kTextureTransformExtension = "KHR_texture_transform";

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

// KHR_texture_transform's `key`: a finite number, `fallback` when absent.
Expected<double> transformNumber(const tinygltf::Value& extension, const char* key, double fallback) {
  if (!extension.Has(key)) return fallback;
  const tinygltf::Value& value = extension.Get(key);
  if (!value.IsNumber() || !std::isfinite(value.GetNumberAsDouble()))
    return makeError(fmt::format("{} {} is not a finite number", kTextureTransformExtension, key));
  return value.GetNumberAsDouble();
}

// KHR_texture_transform's `key`: two finite numbers, `fallback` when absent.
Expected<glm::dvec2> transformPair(const tinygltf::Value& extension, const char* key, glm::dvec2 fallback) {
  if (!extension.Has(key)) return fallback;
  const tinygltf::Value& value = extension.Get(key);
  const auto component = [&](int i) { return value.Get(i).IsNumber() ? value.Get(i).GetNumberAsDouble() : std::nan(""); };
  if (!value.IsArray() || value.ArrayLen() != 2 || !std::isfinite(component(0)) || !std::isfinite(component(1)))
    return makeError(fmt::format("{} {} is not two finite numbers", kTextureTransformExtension, key));
  return glm::dvec2(component(0), component(1));
}

// offset * rotation * scale. The rotation turns u toward -v: glTF's v axis points down, and the
// GLSL listing of the extension's README, which turns u toward +v, is known to be wrong
// (KhronosGroup/glTF#1563); the README's example ("the lower left quadrant"), the TextureTransformTest
// sample model and the implementations follow this sign.
glm::mat3 transformMatrix(glm::dvec2 offset, double rotation, glm::dvec2 scale) {
  const double c = std::cos(rotation), s = std::sin(rotation);
  glm::dmat3 m(1.0);
  m[0] = glm::dvec3(c * scale.x, -s * scale.x, 0.0);
  m[1] = glm::dvec3(s * scale.y, c * scale.y, 0.0);
  m[2] = glm::dvec3(offset, 1.0);
  return glm::mat3(m);
}

// A texture without `source` keeps its image in an extension (KHR_texture_basisu's KTX2,
// EXT_texture_webp's WebP, ...), which stb_image does not decode: named, rather than "image -1".
std::string missingSource(const tinygltf::Texture& texture) {
  for (const auto& [name, extension] : texture.extensions)
    if (extension.IsObject() && extension.Has("source"))
      return fmt::format("its image is only in {}, which is not decoded (PNG and JPEG are)", name);
  return "has no source image";
}

}  // namespace

Expected<TextureCoordinates> textureCoordinates(int texCoord, const tinygltf::ExtensionMap& extensions) {
  TextureCoordinates out;
  out.set = texCoord;
  const auto found = extensions.find(kTextureTransformExtension);
  if (found == extensions.end()) return out;
  const tinygltf::Value& extension = found->second;
  if (!extension.IsObject()) return makeError(fmt::format("{} is not an object", kTextureTransformExtension));
  if (extension.Has("texCoord")) {
    const tinygltf::Value& set = extension.Get("texCoord");
    if (!set.IsInt() || set.Get<int>() < 0)
      return makeError(fmt::format("{} texCoord is not a non-negative integer", kTextureTransformExtension));
    out.set = set.Get<int>();
  }
  ENGINE_TRY_ASSIGN(const glm::dvec2 offset, transformPair(extension, "offset", glm::dvec2(0.0)));
  ENGINE_TRY_ASSIGN(const double rotation, transformNumber(extension, "rotation", 0.0));
  ENGINE_TRY_ASSIGN(const glm::dvec2 scale, transformPair(extension, "scale", glm::dvec2(1.0)));
  out.transform = transformMatrix(offset, rotation, scale);
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(out.transform[c].x) || !std::isfinite(out.transform[c].y))
      return makeError(fmt::format("{} does not fit 32-bit floats", kTextureTransformExtension));
  return out;
}

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
  if (texture.source == -1) return makeError(fmt::format("{}: {}", where, missingSource(texture)));
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
