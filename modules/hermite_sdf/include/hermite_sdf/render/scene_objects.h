#pragma once
// glTF scenes as separate SDF objects: each mesh is baked once, in its own (mesh-local)
// space, into its own SdfAsset, and every node that places the mesh draws that shared asset as an
// instance with the node's world transform. Nodes may instead keep their triangles.
//
// Per-node choice, strongest first:
//   1. SceneObjectOptions::triangleNodes (the command line / settings file): these node names draw
//      triangles; a name no node has is refused by name.
//   2. the node's glTF extras:  "extras": {"hermite_sdf": {"draw": "sdf" | "triangles"}}
//      Other extras are left alone; under "hermite_sdf" an unknown key, a value of the wrong JSON
//      type or an unknown draw name is refused naming the node and the key.
//   3. SceneObjectOptions::defaultDraw, except that a mesh with a see-through material (glTF
//      alphaMode BLEND with an alpha below 1, MASK with one below its cutoff: every SDF method
//      draws an opaque surface) draws triangles (SceneObjects::fallbacks names it).
// A mesh bakes as a shell of the thickness its SDF nodes name, "extras": {"hermite_sdf": {"shell":
// T}} (0 to 1e6 scene units; 0 a solid), else of BakeSettings::shellThickness: a scene of solids
// and sheets names its sheets' thickness, or 0 on its solids. Nodes of one mesh naming two
// thicknesses are refused, naming both (a mesh is one asset).
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/scene/scene_data.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/render/renderable.h"

namespace hsdf {

enum class NodeDraw { Sdf, Triangles };
const char* nodeDrawName(NodeDraw draw);  // "sdf", "triangles"
std::optional<NodeDraw> parseNodeDraw(std::string_view name);

struct SceneObjectOptions {
  NodeDraw defaultDraw = NodeDraw::Sdf;
  std::vector<std::string> triangleNodes;
};

// What a node's extras.hermite_sdf asks for (nullopt: nothing).
struct NodeExtras {
  std::optional<NodeDraw> draw;
  std::optional<double> shellThickness;
};

// The node's own choices from its extras; errors name the node, the key and the value.
engine::Expected<NodeExtras> nodeExtras(const engine::scene::NodeData& node);

// The choice of every node of `scene` (nodes without a mesh get theirs too; nothing draws them).
engine::Expected<std::vector<NodeDraw>> chooseNodeDraws(const engine::scene::SceneData& scene,
                                                        const SceneObjectOptions& options);

// A scene drawn as one SDF (no per-node objects) bakes the meshes of its SDF nodes only, chosen as
// chooseNodeDraws does with the default options: a see-through mesh, or a node whose extras ask for
// triangles, draws triangles beside the SDF instead of being baked into its opaque surface.
struct OneSdfScene {
  std::vector<NodeDraw> draws;           // [node]
  engine::scene::SceneData sdfPart;      // the scene less the meshes of triangle nodes (nodes keep their places)
  std::vector<std::string> seeThrough;   // the see-through meshes, one line each (as SceneObjects::fallbacks)
  bool empty() const;                    // no mesh node left to bake
};
engine::Expected<OneSdfScene> oneSdfScene(const engine::scene::SceneData& scene);

// One mesh of the scene in its own space, as a bake source named after the mesh.
engine::Expected<BakeSource> meshBakeSource(const engine::scene::SceneData& scene, int mesh);

struct SceneObjects {
  std::vector<NodeDraw> draws;                             // [node]
  std::vector<std::shared_ptr<const SdfAsset>> meshAssets;  // [mesh]: null when no SDF node uses it
  std::vector<double> meshShells;  // [mesh]: the shell thickness it bakes with (its nodes' extras, else the settings')
  int bakes = 0;                                           // bakeAsset calls: one per mesh used as SDF
  // Meshes that cannot be an SDF at this K (an open sheet or a flat mesh encloses no volume, a
  // degenerate mesh has no triangle left, a mesh over the kept-cell budget) or at any K (a material
  // that lets what lies behind show somewhere, alphaMode BLEND with an alpha below 1 or MASK below
  // its cutoff, factor times texture, which every SDF method draws opaque: the nodes without an
  // extras choice of their own, unbaked): their nodes draw triangles instead, each line naming the
  // mesh and why ("mesh 0 'leaf': ...").
  std::vector<std::string> fallbacks;
};

// Chooses the nodes' draws and bakes, through bakeAsset, each mesh an SDF node uses, once. A mesh
// that cannot be baked turns its nodes to triangles (SceneObjects::fallbacks): one leaf or decal
// does not cost the scene its SDFs. Errors: the choices (bad extras, unknown names), a K the budget
// refuses for every mesh (planBake), a cancelled bake. `control` covers every bake (progress goes
// 0..1 per mesh). Errors name the mesh.
engine::Expected<SceneObjects> bakeSceneObjects(const engine::scene::SceneData& scene,
                                                const SceneObjectOptions& options, const BakeSettings& settings,
                                                const BakeControl& control = {});

// Puts a HermiteSdfRenderable (the mesh's shared asset, coloured like the mesh's first material)
// on the entity of every SDF node with a mesh; `nodeEntities[i]` is SceneData::nodes[i]'s entity
// and carries its transform. Returns those entities.
std::vector<engine::ecs::Entity> addSdfInstances(const engine::scene::SceneData& scene, const SceneObjects& objects,
                                                 std::span<const engine::ecs::Entity> nodeEntities,
                                                 engine::ecs::Registry& registry);

// Levels of detail of scene objects ([mesh]: the mesh's levels, finest first; empty where no SDF
// node uses the mesh).
using SceneObjectLevels = std::vector<std::vector<std::shared_ptr<const SdfAsset>>>;

// The levels of every mesh an SDF node uses (bakeLodLevels): level 0 is objects.meshAssets[mesh]
// (baked with `finest`, not baked again), then K/2, K/4, ... down to minResolution, each from the
// same mesh. Errors name the mesh and the level's K.
engine::Expected<SceneObjectLevels> bakeSceneObjectLevels(const engine::scene::SceneData& scene,
                                                          const SceneObjects& objects, const BakeSettings& finest,
                                                          int minResolution = kDefaultLodMinResolution);

// Puts a HermiteSdfLod with its mesh's levels (target `pixelsPerCell`) beside the renderable of
// every SDF node (the entities addSdfInstances gave one), so that selectSdfLevels picks a level per
// instance: near instances of a mesh draw its fine level, far ones a coarse one, all in the cells'
// one draw. Returns how many entities got levels.
std::size_t addSdfInstanceLevels(const engine::scene::SceneData& scene, const SceneObjects& objects,
                                 const SceneObjectLevels& levels, std::span<const engine::ecs::Entity> nodeEntities,
                                 float pixelsPerCell, engine::ecs::Registry& registry);

}  // namespace hsdf
