// Viewer::loadScene: glTF meshes, SDFs baked through the module bake job, .hsdf files, the ground.
#include <chrono>
#include <cstdio>
#include <unordered_set>

#include <fmt/format.h>

#include "engine/core/log.h"
#include "engine/render/components.h"
#include "engine/render/scene_instantiate.h"
#include "engine/scene/gltf/gltf_loader.h"
#include "engine/scene/scene_pose.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/core/hsdf_file.h"
#include "hermite_sdf/render/scene_objects.h"
#include "viewer.h"

namespace samples {

using namespace engine;

namespace {

// In double: the float length of a box 1e20 across overflows.
double diagonal(const glm::vec3& lo, const glm::vec3& hi) { return glm::length(glm::dvec3(hi) - glm::dvec3(lo)); }

Status checkDrawableSize(const std::filesystem::path& file, const glm::vec3& lo, const glm::vec3& hi) {
  const double size = diagonal(lo, hi);
  if (size >= kMinSceneSize && size <= kMaxSceneSize) return {};
  return makeError(fmt::format("{}: the scene is {:g} across (bounding-box diagonal); the scene runner draws scenes "
                               "{:g} to {:g} across (32-bit float camera and shaders)",
                               file.string(), size, kMinSceneSize, kMaxSceneSize));
}

// The bake job with a terminal progress line and a summary in the log.
Expected<std::shared_ptr<const hsdf::SdfAsset>> bakeWithProgress(const hsdf::BakeSource& source,
                                                                 const hsdf::BakeSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  int shown = -1;
  hsdf::BakeControl control;
  control.progress = [&shown](float fraction) {
    const int percent = int(fraction * 100.0f);
    if (percent / 10 != shown / 10) std::fprintf(stderr, "\rbaking %3d%%", percent);
    shown = percent;
    return true;
  };
  auto asset = hsdf::bakeAsset(source, settings, control);
  std::fprintf(stderr, "\r");
  if (!asset) return asset.error();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const hsdf::CellStats& stats = (*asset)->classification.stats;
  log::info("baked {}^3 Hermite field in {:.2f} s: {} kept cells ({} crossing, {} ambiguous), {} stored scalars",
            settings.resolution, seconds, stats.kept(), stats.crossing, stats.ambiguous, (*asset)->cells.stored_scalars());
  return asset;
}

// A .hsdf file: its dense field (re-classified) when present, else its cells.
Expected<std::shared_ptr<const hsdf::SdfAsset>> loadSdfFile(const std::filesystem::path& path) {
  const auto contents = hsdf::loadHsdf(path);
  if (!contents) return contents.error();
  const std::string name = path.filename().string();
  // Copies, not moves, out of the optionals: GCC 12 -O3 warns (falsely) about moved-from ones.
  // Both payloads: the stored cells are the baker's (refined with --refine, classified before an
  // fp16 file's rounding), the dense field is the sphere tracers'. Classifying the field again
  // dropped the refinement (2,698 cells stored, 2,721 drawn).
  if (contents->dense && contents->cells) {
    ENGINE_TRY_ASSIGN(const std::shared_ptr<const hsdf::SdfAsset> cells,
                      hsdf::makeSdfAssetFromCells(name, *contents->cells, contents->palette));
    auto asset = std::make_shared<hsdf::SdfAsset>(*cells);
    asset->field = *contents->dense;
    return std::shared_ptr<const hsdf::SdfAsset>(std::move(asset));
  }
  if (contents->dense) return hsdf::makeSdfAsset(name, *contents->dense, contents->grid.bounds(), {}, contents->palette);
  if (contents->cells) return hsdf::makeSdfAssetFromCells(name, *contents->cells, contents->palette);
  return makeError(path.string() + ": holds neither a dense field nor cells");
}

}  // namespace

Status Viewer::loadScene(const SceneDesc& scene, const TuningState& tuning) {
  tuning_ = tuning;
  const bool onlyFile = scene.gltf.empty() && scene.shape.empty();
  if (!scene.sdfFile.empty()) ENGINE_TRY(addSdfFile(scene.sdfFile, onlyFile));
  if (!scene.gltf.empty()) {
    ENGINE_TRY(loadGltf(scene));
  } else if (!scene.shape.empty()) {
    ENGINE_TRY(addBakedSdf(hsdf::BakeSource::fromShape(scene.shape), scene).withContext(scene.shape));
  }
  if (scene.groundPlane) addGroundPlane();
  updateVisibility(tuning_.method);  // the registry shows what the method draws from the start, not only after step()
  scene::updateWorldTransforms(registry_);
  // A thousandth of the scene: reverse-Z float depth keeps its precision with a near plane this close
  // (1 %, as before, clipped a part a thousandth of the scene's size before the fly camera reached it).
  znear_ = float(0.001 * diagonal(boundsMin_, boundsMax_));
  setOrbitView(0);
  setTuning(tuning_);  // a comparison asked for from the start bakes its side (worker thread)
  return {};
}

Status Viewer::loadGltf(const SceneDesc& scene) {
  ENGINE_TRY_ASSIGN(scene::SceneData data, scene::loadGltf(scene.gltf));
  // Posed before the nodes become entities and bakes: the first frame shows the start time.
  ENGINE_TRY_ASSIGN(std::optional<AnimationPlayer> player, startAnimation(scene, data));
  const render::InstantiatedScene instantiated = render::instantiateScene(data, registry_, *pool_);
  if (player && scene.objects) {
    player->attach(instantiated.nodes);
    animation_ = std::move(player);
  }
  collectSceneCameras(instantiated.cameras);
  sceneTriangles_ = !instantiated.renderables.empty();
  if (instantiated.renderables.empty()) {
    log::warn("{}: the scene has no triangle meshes", scene.gltf.string());
  } else {
    boundsMin_ = instantiated.boundsMin;
    boundsMax_ = instantiated.boundsMax;
    ENGINE_TRY(checkDrawableSize(scene.gltf, boundsMin_, boundsMax_));
  }
  if (!scene.sdfFile.empty() || instantiated.renderables.empty()) {
    if (isSdfMethod(tuning_.method) && scene.sdfFile.empty())
      return makeError(scene.gltf.string() + ": no triangle meshes to bake into an SDF");
    return {};
  }
  if (scene.objects)
    return sceneObjects_
        .add(std::make_shared<const scene::SceneData>(std::move(data)), instantiated.nodes, instantiated.renderables,
             meshEntities_)
        .withContext(scene.gltf.string());
  ENGINE_TRY_ASSIGN(const scene::SceneData sdfPart, oneSdfPart(data, instantiated, scene.gltf));
  if (meshEntities_.empty()) return {};  // every mesh draws triangles (oneSdfPart said so)
  sideBySide_ = scene.sideBySide;
  // The SDF looks like the mesh it stands for: the colour of the first primitive drawn (a mesh
  // without a material is drawn in the default material's grey, not in the SDF's own colour).
  for (const scene::NodeData& node : sdfPart.nodes)
    if (node.mesh >= 0 && std::size_t(node.mesh) < data.meshes.size() && !data.meshes[std::size_t(node.mesh)].primitives.empty()) {
      bakes_.setColor(scene::baseColorOf(data, data.meshes[std::size_t(node.mesh)].primitives.front().material));
      break;
    }
  const glm::vec3 origin = bakeOrigin(boundsMin_, boundsMax_);
  auto source = hsdf::BakeSource::fromScene("scene sdf", sdfPart, glm::dvec3(origin));
  // Primitives of several materials bake into a palette (hermite_sdf/core/materials.h), which the
  // entity's colour multiplies: white shows the materials as authored.
  if (source && source->materials) bakes_.setColor(glm::vec4(1.0f));
  if (!isSdfMethod(tuning_.method)) {
    // Baked when an SDF method is picked; a scene that cannot be baked says why then.
    if (source) bakes_.setSource(std::move(*source), origin);
    else bakes_.setError(source.error().withContext(scene.gltf.string()).message);
    return {};
  }
  if (!source) return source.error().withContext(scene.gltf.string());
  return addBakedSdf(std::move(*source), scene, origin).withContext(scene.gltf.string());
}

// The chosen animation (SceneDesc::animation): the scene posed at its start time (what the first
// frame, and a one-SDF bake, show) and its player, from the file's own pose. Without --objects it is
// not played, and said so: the one SDF bakes every node in one field, so a moving part would need
// the whole scene baked again each frame.
Expected<std::optional<AnimationPlayer>> Viewer::startAnimation(const SceneDesc& scene, scene::SceneData& data) {
  ENGINE_TRY_ASSIGN(const std::optional<std::size_t> chosen,
                    chooseAnimation(data, scene.animation).withContext(scene.gltf.string()));
  if (!chosen) return std::optional<AnimationPlayer>{};
  const scene::AnimationData& animation = data.animations[*chosen];
  AnimationPlayer player(animation, scene::restPose(data), scene.animationTime);
  scene::poseScene(data, player.rest(), animation, scene::loopTime(animation, scene.animationTime));
  if (!scene.objects)
    log::warn("{}: animation {} '{}' is drawn still at {} s: the one SDF bakes the whole scene, so its parts cannot "
              "move without a re-bake; --objects plays it (each mesh an SDF object moved per frame)",
              scene.gltf.string(), *chosen, animation.name, scene.animationTime);
  return std::optional<AnimationPlayer>{std::move(player)};
}

// The part of a glTF scene its one SDF bakes (hsdf::oneSdfScene: a see-through mesh drawn opaque
// would hide what lies behind it), naming each see-through mesh as SdfObjects does; the parts of
// the other nodes stay triangles, drawn beside the SDF by every method. meshEntities_: the parts the
// SDF stands for, none when every mesh node draws triangles (said here: nothing is baked).
Expected<scene::SceneData> Viewer::oneSdfPart(const scene::SceneData& data,
                                              const render::InstantiatedScene& instantiated,
                                              const std::filesystem::path& file) {
  ENGINE_TRY_ASSIGN(hsdf::OneSdfScene split, hsdf::oneSdfScene(data).withContext(file.string()));
  for (const std::string& line : split.seeThrough) log::warn("{}", line);
  std::unordered_set<ecs::Entity> triangleNodes;
  for (std::size_t n = 0; n < split.draws.size() && n < instantiated.nodes.size(); ++n)
    if (split.draws[n] == hsdf::NodeDraw::Triangles) triangleNodes.insert(instantiated.nodes[n]);
  meshEntities_.clear();
  for (const ecs::Entity part : instantiated.renderables)
    if (!triangleNodes.contains(registry_.get<scene::Parent>(part).entity)) meshEntities_.push_back(part);
  if (meshEntities_.empty()) {
    const std::string nothing = fmt::format("{}: every mesh is drawn as triangles (see-through materials, or the "
                                            "nodes' extras): nothing to bake into an SDF; every method draws the "
                                            "triangles",
                                            file.string());
    log::warn("{}", nothing);
    bakes_.setError(nothing);
  }
  return std::move(split.sdfPart);
}

// Where a flattened scene is baked about: its centre when the scene lies farther from the world
// origin than twice its size, else the origin. Far away, world positions in float lose what the
// cells need (1e6 units from the origin float holds 0.06, two cells of a unit cube at K = 32): the
// scene is baked about its centre, in double (flattenTriangles), and the SDF entity placed there.
// The centre is a float, so the entity's translation holds it exactly.
glm::vec3 Viewer::bakeOrigin(const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float size = glm::length(hi - lo);
  return glm::length(centre) > 2.0f * size ? centre : glm::vec3(0.0f);
}

// Bakes `source` at the tuning's K and padding and adds it: as the scene when there are no meshes,
// beside them with sideBySide, else in their place (they stay, hidden, for Method::Mesh).
Status Viewer::addBakedSdf(hsdf::BakeSource source, const SceneDesc& scene, const glm::vec3& origin) {
  const hsdf::BakeSettings settings = bakes_.settings();
  ENGINE_TRY_ASSIGN(std::shared_ptr<const hsdf::SdfAsset> asset, bakeWithProgress(source, settings));
  glm::vec3 offset = origin;  // the source's space in the world (bakeOrigin)
  if (meshEntities_.empty()) {  // the baked shape is the scene
    boundsMin_ = glm::vec3(asset->surfaceBounds.min) + origin;
    boundsMax_ = glm::vec3(asset->surfaceBounds.max) + origin;
  } else if (scene.sideBySide) {
    const float shift = 1.25f * (boundsMax_.x - boundsMin_.x);
    offset.x += shift;
    boundsMax_.x += shift;
  }
  bakes_.add(std::move(asset), offset);
  bakes_.setSource(std::move(source), origin);
  bakes_.setBaked(bakeKey(settings));
  return {};
}

// Draws a baked .hsdf file; `frameIt`: its grid bounds are the scene's.
Status Viewer::addSdfFile(const std::filesystem::path& file, bool frameIt) {
  ENGINE_TRY_ASSIGN(std::shared_ptr<const hsdf::SdfAsset> asset, loadSdfFile(file));
  if (!drawsCells(tuning_.method) && asset->field.samples.empty())
    return makeError(fmt::format("{}: holds only cells; --method {} needs the dense field (bake without --cells)",
                                 file.string(), methodName(tuning_.method)));
  if (comparing(tuning_) && needsDenseField(tuning_.compareMethod) && asset->field.samples.empty())
    return makeError(fmt::format("{}: holds only cells; the compared side ({} with --split or --difference) needs "
                                 "the dense field: --compare-method cells, or a file baked without --cells",
                                 file.string(), methodName(tuning_.compareMethod)));
  const hsdf::Aabb bounds = asset->cells.grid.bounds();
  ENGINE_TRY(checkDrawableSize(file, glm::vec3(bounds.min), glm::vec3(bounds.max)));
  if (frameIt) {
    boundsMin_ = glm::vec3(bounds.min);
    boundsMax_ = glm::vec3(bounds.max);
  }
  bakes_.setBaked({int(asset->cells.grid.resolution), bakes_.baked().padding, bakes_.baked().shellThickness});
  tuning_.resolution = int(asset->cells.grid.resolution);  // what the panel and saved settings say
  // A file of several materials shows its palette as authored (white multiplies it).
  if (!asset->palette.empty()) bakes_.setColor(glm::vec4(1.0f));
  bakes_.add(std::move(asset), glm::vec3(0.0f));  // before the glTF scene's color is known: uncolored
  return {};
}

// A thin box under the scene so that occlusion and the depth prepass have something to show.
void Viewer::addGroundPlane() {
  const glm::vec3 size = boundsMax_ - boundsMin_;
  const float extent = 1.5f * std::max(size.x, size.z);
  const glm::vec3 center(0.5f * (boundsMin_.x + boundsMax_.x), boundsMin_.y, 0.5f * (boundsMin_.z + boundsMax_.z));
  const glm::vec3 corners[4] = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}};
  std::vector<glm::vec3> positions, normals;
  for (const glm::vec3& corner : corners) {
    positions.push_back(corner);
    normals.emplace_back(0.0f, 1.0f, 0.0f);
  }
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};
  const ecs::Entity ground = registry_.create();
  scene::Transform transform;
  transform.translation = center;
  transform.scale = glm::vec3(extent, 1.0f, extent);
  registry_.emplace<scene::Transform>(ground, transform);
  render::MeshRenderable renderable;
  renderable.mesh = pool_->add(positions, normals, indices);
  renderable.color = glm::vec4(0.35f, 0.37f, 0.4f, 1.0f);
  renderable.roughness = 0.9f;
  registry_.emplace<render::MeshRenderable>(ground, renderable);
  registry_.emplace<scene::Name>(ground, scene::Name{"ground"});
}

}  // namespace samples
