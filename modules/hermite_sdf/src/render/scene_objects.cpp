#include "hermite_sdf/render/scene_objects.h"

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "engine/core/log.h"
#include "engine/scene/gltf/gltf_loader.h"

namespace hsdf {
namespace {

using Json = nlohmann::json;
constexpr const char* kExtrasKey = "hermite_sdf";
constexpr double kMaxNodeShellThickness = 1e6;  // as the tuning's --shell (samples/common/tuning.h)

std::string nodeLabel(const engine::scene::NodeData& node) { return fmt::format("node '{}'", node.name); }

// extras.hermite_sdf.draw, checked: a string, a known name.
engine::Expected<std::optional<NodeDraw>> readDrawKey(const Json& draw) {
  if (!draw.is_string())
    return engine::makeError(fmt::format("extras.{}.draw is a JSON {}, not a string", kExtrasKey, draw.type_name()));
  const std::string name = draw.get<std::string>();
  if (const auto parsed = parseNodeDraw(name)) return std::optional<NodeDraw>{*parsed};
  return engine::makeError(fmt::format("extras.{}.draw: '{}' is not one of sdf, triangles", kExtrasKey, name));
}

// extras.hermite_sdf.shell, checked: a number in the range the tuning's own thickness takes.
engine::Expected<std::optional<double>> readShellKey(const Json& shell) {
  if (!shell.is_number())
    return engine::makeError(fmt::format("extras.{}.shell is a JSON {}, not a number", kExtrasKey, shell.type_name()));
  const double thickness = shell.get<double>();
  if (!(thickness >= 0.0 && thickness <= kMaxNodeShellThickness))
    return engine::makeError(fmt::format("extras.{}.shell: {:g} is not between 0 and {:g}", kExtrasKey, thickness,
                                         kMaxNodeShellThickness));
  return std::optional<double>{thickness};
}

// extras.hermite_sdf, checked: an object of known keys only.
engine::Expected<NodeExtras> readNodeExtras(const Json& settings) {
  if (!settings.is_object())
    return engine::makeError(fmt::format("extras.{} is a JSON {}, not an object", kExtrasKey, settings.type_name()));
  NodeExtras extras;
  for (const auto& [key, value] : settings.items()) {
    if (key == "draw") {
      ENGINE_TRY_ASSIGN(extras.draw, readDrawKey(value));
    } else if (key == "shell") {
      ENGINE_TRY_ASSIGN(extras.shellThickness, readShellKey(value));
    } else {
      return engine::makeError(fmt::format("extras.{}.{}: unknown key (known: draw, shell)", kExtrasKey, key));
    }
  }
  return extras;
}

// Sets, not searches per name and node: an instanced scene has a million nodes.
engine::Status checkNamesExist(const engine::scene::SceneData& scene, const std::vector<std::string>& names) {
  if (names.empty()) return {};
  std::unordered_set<std::string_view> nodeNames;
  for (const engine::scene::NodeData& node : scene.nodes) nodeNames.insert(node.name);
  for (const std::string& name : names)
    if (!nodeNames.contains(name))
      return engine::makeError(fmt::format("triangle nodes: the scene has no node named '{}'", name));
  return {};
}

}  // namespace

const char* nodeDrawName(NodeDraw draw) { return draw == NodeDraw::Sdf ? "sdf" : "triangles"; }

std::optional<NodeDraw> parseNodeDraw(std::string_view name) {
  if (name == "sdf") return NodeDraw::Sdf;
  if (name == "triangles") return NodeDraw::Triangles;
  return std::nullopt;
}

engine::Expected<NodeExtras> nodeExtras(const engine::scene::NodeData& node) {
  if (node.extras.empty()) return NodeExtras{};
  const Json extras = Json::parse(node.extras, nullptr, false);
  if (!extras.is_object() || !extras.contains(kExtrasKey)) return NodeExtras{};
  return readNodeExtras(extras.at(kExtrasKey)).withContext(nodeLabel(node));
}

namespace {

// Every node's draw and own extras, in one pass over the extras (an instanced scene has a million
// nodes).
struct NodeChoices {
  std::vector<NodeDraw> draws;     // [node]
  std::vector<NodeExtras> extras;  // [node]
  // The see-through meshes that nodes without a choice of their own draw as triangles, one line
  // each (SceneObjects::fallbacks).
  std::vector<std::string> seeThrough;
};

// The smallest alpha `material` draws anywhere: its base colour factor's times the smallest texel
// alpha of its base colour texture (filtering blends texels, so none is smaller).
float smallestAlpha(const engine::scene::SceneData& scene, const engine::scene::MaterialData& material) {
  std::uint8_t texel = 255;
  if (material.baseColorTexture >= 0 && std::size_t(material.baseColorTexture) < scene.textures.size()) {
    const std::vector<std::uint8_t>& rgba = scene.textures[std::size_t(material.baseColorTexture)].rgba;
    for (std::size_t i = 3; i < rgba.size(); i += 4) texel = std::min(texel, rgba[i]);
  }
  return material.baseColor.a * float(texel) / 255.0f;
}

// Why `mesh` cannot be drawn as an SDF whatever K: the first of its materials that lets what lies
// behind it show (glTF alphaMode BLEND with an alpha below 1 somewhere, a glass pane; MASK with an
// alpha below its cutoff somewhere, a card cut out by its texture), which every SDF method would
// draw opaque, hiding what the triangles show through it. Empty: none.
std::string seeThroughMaterial(const engine::scene::SceneData& scene, int mesh) {
  for (const engine::scene::MeshPrimitiveData& primitive : scene.meshes[std::size_t(mesh)].primitives) {
    if (primitive.material < 0 || std::size_t(primitive.material) >= scene.materials.size()) continue;
    const engine::scene::MaterialData& material = scene.materials[std::size_t(primitive.material)];
    const float alpha = material.alphaBlend || material.alphaCutoff ? smallestAlpha(scene, material) : 1.0f;
    if (material.alphaBlend ? alpha < 1.0f : material.alphaCutoff && alpha < *material.alphaCutoff)
      return fmt::format("material {} '{}' is alphaMode {}, which an SDF draws opaque (a node's extras {}.draw "
                         "\"sdf\" draws it as one anyway)",
                         primitive.material, material.name, material.alphaBlend ? "BLEND" : "MASK", kExtrasKey);
  }
  return {};
}

// A node without a choice of its own draws a see-through mesh as triangles (seeThroughMaterial);
// the mesh is named once in `choices`. `reasons` caches each mesh's reason ("" none, nullopt not
// yet asked): a million instances share a few meshes.
NodeDraw defaultDrawOf(const engine::scene::SceneData& scene, int mesh, NodeDraw draw,
                       std::vector<std::optional<std::string>>& reasons, NodeChoices& choices) {
  if (draw != NodeDraw::Sdf || mesh < 0 || std::size_t(mesh) >= scene.meshes.size()) return draw;
  std::optional<std::string>& reason = reasons[std::size_t(mesh)];
  if (!reason) {
    reason = seeThroughMaterial(scene, mesh);
    if (!reason->empty())
      choices.seeThrough.push_back(
          fmt::format("mesh {} '{}': drawn as triangles: {}", mesh, scene.meshes[std::size_t(mesh)].name, *reason));
  }
  return reason->empty() ? NodeDraw::Sdf : NodeDraw::Triangles;
}

engine::Expected<NodeChoices> chooseNodes(const engine::scene::SceneData& scene, const SceneObjectOptions& options) {
  ENGINE_TRY(checkNamesExist(scene, options.triangleNodes));
  NodeChoices choices;
  choices.draws.reserve(scene.nodes.size());
  choices.extras.reserve(scene.nodes.size());
  const std::unordered_set<std::string_view> listed(options.triangleNodes.begin(), options.triangleNodes.end());
  std::vector<std::optional<std::string>> seeThrough(scene.meshes.size());
  for (const engine::scene::NodeData& node : scene.nodes) {
    ENGINE_TRY_ASSIGN(NodeExtras own, nodeExtras(node));
    const bool forced = listed.contains(node.name);
    choices.draws.push_back(forced     ? NodeDraw::Triangles
                            : own.draw ? *own.draw
                                       : defaultDrawOf(scene, node.mesh, options.defaultDraw, seeThrough, choices));
    choices.extras.push_back(own);
  }
  return choices;
}

// The thickness each mesh bakes with: the one its SDF nodes name (they must agree: one mesh is one
// asset), else `tuned`.
engine::Expected<std::vector<double>> chooseMeshShells(const engine::scene::SceneData& scene,
                                                       const NodeChoices& choices, double tuned) {
  std::vector<double> shells(scene.meshes.size(), tuned);
  std::vector<int> namedBy(scene.meshes.size(), -1);  // the first node that named the mesh's thickness
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    const int mesh = scene.nodes[n].mesh;
    const std::optional<double> own = choices.extras[n].shellThickness;
    if (mesh < 0 || choices.draws[n] != NodeDraw::Sdf || !own) continue;
    int& first = namedBy[std::size_t(mesh)];
    if (first >= 0 && shells[std::size_t(mesh)] != *own)
      return engine::makeError(fmt::format(
          "mesh {} '{}': node '{}' asks for extras.{}.shell {:g} and node '{}' for {:g}: one mesh bakes one thickness",
          mesh, scene.meshes[std::size_t(mesh)].name, scene.nodes[std::size_t(first)].name, kExtrasKey,
          shells[std::size_t(mesh)], scene.nodes[n].name, *own));
    if (first < 0) first = int(n);
    shells[std::size_t(mesh)] = *own;
  }
  return shells;
}

}  // namespace

engine::Expected<std::vector<NodeDraw>> chooseNodeDraws(const engine::scene::SceneData& scene,
                                                        const SceneObjectOptions& options) {
  ENGINE_TRY_ASSIGN(NodeChoices choices, chooseNodes(scene, options));
  return std::move(choices.draws);
}

bool OneSdfScene::empty() const {
  return std::none_of(sdfPart.nodes.begin(), sdfPart.nodes.end(),
                      [](const engine::scene::NodeData& node) { return node.mesh >= 0; });
}

engine::Expected<OneSdfScene> oneSdfScene(const engine::scene::SceneData& scene) {
  ENGINE_TRY_ASSIGN(NodeChoices choices, chooseNodes(scene, {}));
  OneSdfScene split;
  split.sdfPart = scene;
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    if (choices.draws[n] == NodeDraw::Triangles) split.sdfPart.nodes[n].mesh = -1;
  split.draws = std::move(choices.draws);
  split.seeThrough = std::move(choices.seeThrough);
  return split;
}

// A scene of the one mesh at the identity: flattening it gives the mesh in its own space.
engine::Expected<BakeSource> meshBakeSource(const engine::scene::SceneData& scene, int mesh) {
  if (mesh < 0 || std::size_t(mesh) >= scene.meshes.size())
    return engine::makeError(fmt::format("mesh {} is out of range (the scene has {})", mesh, scene.meshes.size()));
  engine::scene::SceneData single;
  single.meshes.push_back(scene.meshes[std::size_t(mesh)]);
  single.nodes.emplace_back().mesh = 0;
  single.materials = scene.materials;  // its primitives' materials, for a mesh of several (materials.h)
  const std::string& name = scene.meshes[std::size_t(mesh)].name;
  return BakeSource::fromScene(name.empty() ? fmt::format("mesh {}", mesh) : name, single);
}

namespace {

// Every node of `mesh` draws triangles; the reason is kept for the caller to report.
void fallBackToTriangles(const engine::scene::SceneData& scene, int mesh, std::string reason, SceneObjects& objects) {
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    if (scene.nodes[n].mesh == mesh) objects.draws[n] = NodeDraw::Triangles;
  objects.fallbacks.push_back(std::move(reason));
}

// One mesh's asset, or the reason it has none (Expected's error) and whether that reason stops the
// scene (`fatal`: a K refused for every mesh, a cancelled bake) rather than this mesh only.
engine::Expected<std::shared_ptr<const SdfAsset>> bakeMesh(const engine::scene::SceneData& scene, int mesh,
                                                           const BakeSettings& settings, const BakeControl& control,
                                                           bool& fatal) {
  fatal = false;
  ENGINE_TRY_ASSIGN(BakeSource source, meshBakeSource(scene, mesh));
  ENGINE_TRY_ASSIGN(PreparedSource prepared, prepareSource(source, settings));  // a degenerate mesh: this mesh only
  logPreparedSource(prepared);
  const auto grid = planBake(prepared, settings);
  if (!grid) {
    fatal = true;  // the budget's K, samples or bytes: the same K refuses every mesh
    return grid.error();
  }
  if (const auto thin = thinShellWarning(settings, *grid)) engine::log::warn("bake: {}: {}", source.name, *thin);
  bool refused = false;  // a progress callback that asks to stop cancels the whole scene
  BakeControl watched = control;
  if (control.progress)
    watched.progress = [&control, &refused](float fraction) {
      refused = !control.progress(fraction);
      return !refused;
    };
  auto asset = bakeAsset(prepared, settings, watched);
  fatal = !asset && (refused || (control.cancel != nullptr && control.cancel->isCancelled()));
  return asset;
}

}  // namespace

engine::Expected<SceneObjects> bakeSceneObjects(const engine::scene::SceneData& scene,
                                                const SceneObjectOptions& options, const BakeSettings& settings,
                                                const BakeControl& control) {
  SceneObjects objects;
  ENGINE_TRY_ASSIGN(NodeChoices choices, chooseNodes(scene, options));
  ENGINE_TRY_ASSIGN(objects.meshShells, chooseMeshShells(scene, choices, settings.shellThickness));
  objects.draws = std::move(choices.draws);
  objects.fallbacks = std::move(choices.seeThrough);
  objects.meshAssets.resize(scene.meshes.size());
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    const int mesh = scene.nodes[n].mesh;
    if (mesh < 0 || objects.draws[n] != NodeDraw::Sdf || objects.meshAssets[std::size_t(mesh)]) continue;
    const std::string where = fmt::format("mesh {} '{}'", mesh, scene.meshes[std::size_t(mesh)].name);
    if (scene.meshes[std::size_t(mesh)].primitives.empty()) {  // its points or lines were skipped at load
      fallBackToTriangles(scene, mesh, where + ": no triangles to bake or draw: its nodes draw nothing", objects);
      continue;
    }
    bool fatal = false;
    BakeSettings own = settings;
    own.shellThickness = objects.meshShells[std::size_t(mesh)];
    auto asset = bakeMesh(scene, mesh, own, control, fatal);
    ++objects.bakes;
    if (asset) {
      objects.meshAssets[std::size_t(mesh)] = std::move(*asset);
    } else if (fatal) {
      return asset.error().withContext(where);
    } else {
      fallBackToTriangles(scene, mesh, where + ": drawn as triangles: " + asset.error().message, objects);
    }
  }
  return objects;
}

std::vector<engine::ecs::Entity> addSdfInstances(const engine::scene::SceneData& scene, const SceneObjects& objects,
                                                 std::span<const engine::ecs::Entity> nodeEntities,
                                                 engine::ecs::Registry& registry) {
  std::vector<engine::ecs::Entity> added;
  for (std::size_t n = 0; n < scene.nodes.size() && n < nodeEntities.size(); ++n) {
    const int mesh = scene.nodes[n].mesh;
    if (mesh < 0 || objects.draws[n] != NodeDraw::Sdf || !objects.meshAssets[std::size_t(mesh)]) continue;
    HermiteSdfRenderable renderable;
    renderable.asset = objects.meshAssets[std::size_t(mesh)];
    const auto& primitives = scene.meshes[std::size_t(mesh)].primitives;
    // As its triangles are drawn (a mesh without a material too): one material, its colour; several,
    // white, so that the asset's palette (materials.h) shows them as authored.
    renderable.color = !renderable.asset->palette.empty()
                           ? glm::vec4(1.0f)
                           : engine::scene::baseColorOf(scene, primitives.empty() ? -1 : primitives.front().material);
    registry.emplace<HermiteSdfRenderable>(nodeEntities[n], std::move(renderable));
    added.push_back(nodeEntities[n]);
  }
  return added;
}

engine::Expected<SceneObjectLevels> bakeSceneObjectLevels(const engine::scene::SceneData& scene,
                                                          const SceneObjects& objects, const BakeSettings& finest,
                                                          int minResolution) {
  SceneObjectLevels levels(objects.meshAssets.size());
  for (std::size_t mesh = 0; mesh < objects.meshAssets.size() && mesh < scene.meshes.size(); ++mesh) {
    if (!objects.meshAssets[mesh]) continue;
    ENGINE_TRY_ASSIGN(BakeSource source, meshBakeSource(scene, int(mesh)));
    const std::string where = fmt::format("mesh {} '{}'", mesh, scene.meshes[mesh].name);
    BakeSettings own = finest;
    if (mesh < objects.meshShells.size()) own.shellThickness = objects.meshShells[mesh];
    ENGINE_TRY_ASSIGN(levels[mesh], bakeLodLevels(source, own, minResolution, objects.meshAssets[mesh]).withContext(where));
  }
  return levels;
}

std::size_t addSdfInstanceLevels(const engine::scene::SceneData& scene, const SceneObjects& objects,
                                 const SceneObjectLevels& levels, std::span<const engine::ecs::Entity> nodeEntities,
                                 float pixelsPerCell, engine::ecs::Registry& registry) {
  std::size_t added = 0;
  for (std::size_t n = 0; n < scene.nodes.size() && n < nodeEntities.size(); ++n) {
    const int mesh = scene.nodes[n].mesh;
    if (mesh < 0 || objects.draws[n] != NodeDraw::Sdf || std::size_t(mesh) >= levels.size() ||
        levels[std::size_t(mesh)].empty() || !registry.has<HermiteSdfRenderable>(nodeEntities[n]))
      continue;
    HermiteSdfLod lod;
    lod.levels = levels[std::size_t(mesh)];
    lod.pixelsPerCell = pixelsPerCell;
    registry.emplaceOrReplace<HermiteSdfLod>(nodeEntities[n], std::move(lod));
    ++added;
  }
  return added;
}

}  // namespace hsdf
