// glTF scenes as separate SDF objects (hermite_sdf/render/scene_objects.h): one bake per mesh shared by
// every node that places it, the per-node choice of SDF or triangles (extras, options), bad extras
// refused by name, and the committed sample scene.
#include "hermite_sdf/render/scene_objects.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/scene/gltf/gltf_loader.h"
#include "engine/scene/transform.h"

namespace hsdf {
namespace {

using engine::scene::MeshData;
using engine::scene::NodeData;
using engine::scene::SceneData;

// A closed axis-aligned box from lo to hi, wound counter-clockwise seen from outside.
MeshData boxMesh(std::string name, glm::vec3 lo, glm::vec3 hi) {
  engine::scene::MeshPrimitiveData p;
  for (int corner = 0; corner < 8; ++corner)
    p.positions.emplace_back((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
  p.normals.assign(8, glm::vec3(0.0f, 1.0f, 0.0f));  // not read by the bake
  p.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return {std::move(name), {std::move(p)}};
}

NodeData node(std::string name, int mesh, glm::vec3 translation, std::string extras = {}) {
  NodeData n;
  n.name = std::move(name);
  n.mesh = mesh;
  n.local = n.world = glm::translate(glm::mat4(1.0f), translation);
  n.extras = std::move(extras);
  return n;
}

// Two meshes, six nodes: "cube" placed four times, "slab" twice, far from the origin.
SceneData twoMeshScene() {
  SceneData scene;
  scene.meshes.push_back(boxMesh("cube", glm::vec3(-1.0f), glm::vec3(1.0f)));
  scene.meshes.push_back(boxMesh("slab", glm::vec3(-2.0f, -0.5f, -1.0f), glm::vec3(2.0f, 0.5f, 1.0f)));
  for (int i = 0; i < 4; ++i) scene.nodes.push_back(node("cube" + std::to_string(i), 0, glm::vec3(10.0f * float(i), 0, 0)));
  for (int i = 0; i < 2; ++i) scene.nodes.push_back(node("slab" + std::to_string(i), 1, glm::vec3(0, 0, 10.0f + 10.0f * float(i))));
  return scene;
}

BakeSettings smallBake() {
  BakeSettings settings;
  settings.resolution = 12;
  return settings;
}

std::string errorOf(const SceneData& scene, const SceneObjectOptions& options = {}) {
  const auto draws = chooseNodeDraws(scene, options);
  return draws ? std::string("(accepted)") : draws.error().message;
}

// Tricky: sharing must hold per mesh, not per scene: six nodes, two bakes, two distinct assets,
// and every node's component points at its own mesh's asset.
TEST(SceneObjects, EachMeshBakedOnceAndSharedByItsNodes) {
  const SceneData scene = twoMeshScene();
  const auto objects = bakeSceneObjects(scene, {}, smallBake());
  ASSERT_TRUE(objects) << objects.error().message;
  EXPECT_EQ(objects->bakes, 2);
  ASSERT_EQ(objects->meshAssets.size(), 2u);
  ASSERT_TRUE(objects->meshAssets[0] && objects->meshAssets[1]);
  EXPECT_NE(objects->meshAssets[0]->id, objects->meshAssets[1]->id);
  EXPECT_EQ(objects->meshAssets[0]->name, "cube");

  engine::ecs::Registry registry;
  std::vector<engine::ecs::Entity> entities;
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) entities.push_back(registry.create());
  const auto added = addSdfInstances(scene, *objects, entities, registry);
  ASSERT_EQ(added.size(), 6u);
  std::set<std::uint64_t> ids;
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    const auto& renderable = registry.get<HermiteSdfRenderable>(entities[n]);
    EXPECT_EQ(renderable.asset.get(), objects->meshAssets[std::size_t(scene.nodes[n].mesh)].get()) << n;
    ids.insert(renderable.asset->id);
  }
  EXPECT_EQ(ids.size(), 2u);
}

// Tricky: an SDF object has the colour its triangles are drawn in: its first primitive's material,
// and for a mesh without one the default material's grey, not the SDF component's own default
// (a cube without a material was pink as an SDF and grey as triangles, found by a helper).
TEST(SceneObjects, EachObjectTakesTheColourItsTrianglesAreDrawnIn) {
  SceneData scene = twoMeshScene();
  scene.materials.push_back({"blue", glm::vec4(0.1f, 0.2f, 0.9f, 1.0f)});
  scene.meshes[1].primitives.front().material = 0;  // the slab; the cube has none
  const auto objects = bakeSceneObjects(scene, {}, smallBake());
  ASSERT_TRUE(objects) << objects.error().message;
  engine::ecs::Registry registry;
  std::vector<engine::ecs::Entity> entities;
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) entities.push_back(registry.create());
  addSdfInstances(scene, *objects, entities, registry);
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    EXPECT_EQ(registry.get<HermiteSdfRenderable>(entities[n]).color,
              scene.nodes[n].mesh == 1 ? glm::vec4(0.1f, 0.2f, 0.9f, 1.0f) : engine::scene::MaterialData{}.baseColor)
        << n;
}

// Tricky: the asset is the mesh in its own space; the node's placement (10 units away) must not be
// baked in, or every instance would be drawn twice offset.
TEST(SceneObjects, AssetsAreBakedInTheMeshsOwnSpace) {
  const SceneData scene = twoMeshScene();
  const auto objects = bakeSceneObjects(scene, {}, smallBake());
  ASSERT_TRUE(objects) << objects.error().message;
  const Aabb& slab = objects->meshAssets[1]->surfaceBounds;
  EXPECT_NEAR(slab.min.x, -2.0, 1e-5);
  EXPECT_NEAR(slab.max.y, 0.5, 1e-5);
  EXPECT_NEAR(slab.max.z, 1.0, 1e-5);
}

// Tricky: a mesh placed only by triangle nodes is not baked at all; the options' list beats the
// node's own "sdf"; the default applies only to nodes without a choice.
TEST(SceneObjects, PerNodeChoiceFromExtrasOptionsAndDefault) {
  SceneData scene = twoMeshScene();
  scene.nodes[0].extras = R"({"hermite_sdf": {"draw": "triangles"}, "author": "x"})";
  scene.nodes[1].extras = R"({"hermite_sdf": {"draw": "sdf"}})";
  scene.nodes[2].extras = R"({"author": "not ours"})";
  for (int n : {4, 5}) scene.nodes[std::size_t(n)].extras = R"({"hermite_sdf": {"draw": "triangles"}})";

  SceneObjectOptions options;
  const auto draws = chooseNodeDraws(scene, options);
  ASSERT_TRUE(draws) << draws.error().message;
  EXPECT_EQ((*draws)[0], NodeDraw::Triangles);
  EXPECT_EQ((*draws)[1], NodeDraw::Sdf);
  EXPECT_EQ((*draws)[2], NodeDraw::Sdf);
  const auto objects = bakeSceneObjects(scene, options, smallBake());
  ASSERT_TRUE(objects) << objects.error().message;
  EXPECT_EQ(objects->bakes, 1);
  EXPECT_FALSE(objects->meshAssets[1]) << "the slab is drawn only as triangles";

  options.defaultDraw = NodeDraw::Triangles;
  options.triangleNodes = {"cube1"};
  const auto forced = chooseNodeDraws(scene, options);
  ASSERT_TRUE(forced) << forced.error().message;
  EXPECT_EQ((*forced)[1], NodeDraw::Triangles) << "the list beats the node's own sdf";
  EXPECT_EQ((*forced)[2], NodeDraw::Triangles) << "no hermite_sdf key: the default";
  EXPECT_EQ((*forced)[3], NodeDraw::Triangles);
}

// Tricky: every SDF method draws an opaque surface, so a mesh that lets what lies behind it show
// (alphaMode BLEND: a glass pane; MASK: a card cut out by its alpha) drawn as an SDF hid what its
// triangles show through it (the explorer of session 41: a pane of alpha 0.3 before a cube, cells
// under --objects, hid the whole cube). Such a mesh's nodes draw triangles unless a node's own
// extras ask for an SDF, and the mesh is named once with its material. Opaque meshes are untouched,
// and so are BLEND and MASK materials whose every texel is drawn opaque (exporters write them):
// the slab's two primitives, a BLEND of alpha 1 and a MASK of alpha 0.6 over its cutoff 0.5. The
// card's MASK has that alpha too, but one texel of its texture has alpha 0.
TEST(SceneObjects, SeeThroughMeshesDrawTrianglesUnlessTheirNodeAsksForAnSdf) {
  SceneData scene = twoMeshScene();
  scene.materials.push_back({"stone"});
  scene.materials.push_back({"glass", glm::vec4(0.1f, 0.3f, 0.9f, 0.3f)});
  scene.materials.back().alphaBlend = true;
  scene.materials.push_back({"leaves", glm::vec4(1.0f, 1.0f, 1.0f, 0.6f)});
  scene.materials.back().alphaCutoff = 0.5f;
  scene.materials.back().baseColorTexture = 0;
  scene.textures.push_back({"leaf", 2, 1, {255, 255, 255, 255, 0, 255, 0, 0}});
  scene.materials.push_back({"opaque glass"});
  scene.materials.back().alphaBlend = true;
  scene.materials.push_back({"opaque card", glm::vec4(1.0f, 1.0f, 1.0f, 0.6f)});
  scene.materials.back().alphaCutoff = 0.5f;
  scene.meshes[1].primitives.push_back(scene.meshes[1].primitives.front());
  scene.meshes[1].primitives[0].material = 3;  // the slabs
  scene.meshes[1].primitives[1].material = 4;
  // A second primitive: one see-through primitive is enough to see through the mesh.
  for (const int material : {1, 2}) {
    MeshData mesh = boxMesh(material == 1 ? "pane" : "card", glm::vec3(-1.0f, -1.0f, -0.1f), glm::vec3(1.0f, 1.0f, 0.1f));
    mesh.primitives.push_back(mesh.primitives.front());
    mesh.primitives[0].material = 0;
    mesh.primitives[1].material = material;
    scene.meshes.push_back(std::move(mesh));
  }
  scene.meshes[0].primitives.front().material = 0;  // the cubes: opaque
  scene.nodes.push_back(node("pane0", 2, glm::vec3(0, 5, 0)));
  scene.nodes.push_back(node("pane1", 2, glm::vec3(0, 10, 0)));
  scene.nodes.push_back(node("card", 3, glm::vec3(0, 15, 0)));
  scene.nodes.push_back(node("card as sdf", 3, glm::vec3(0, 20, 0), R"({"hermite_sdf": {"draw": "sdf"}})"));

  const auto objects = bakeSceneObjects(scene, {}, smallBake());
  ASSERT_TRUE(objects) << objects.error().message;
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    EXPECT_EQ(objects->draws[n], scene.nodes[n].name.starts_with("pane") || scene.nodes[n].name == "card"
                                     ? NodeDraw::Triangles
                                     : NodeDraw::Sdf)
        << scene.nodes[n].name;
  EXPECT_FALSE(objects->meshAssets[2]) << "no node draws the pane as an SDF: not baked";
  EXPECT_TRUE(objects->meshAssets[3]) << "the card's own extras ask for an SDF";
  ASSERT_EQ(objects->fallbacks.size(), 2u);
  EXPECT_NE(objects->fallbacks[0].find("mesh 2 'pane': drawn as triangles: material 1 'glass' is alphaMode BLEND"),
            std::string::npos)
      << objects->fallbacks[0];
  EXPECT_NE(objects->fallbacks[1].find("mesh 3 'card': drawn as triangles: material 2 'leaves' is alphaMode MASK"),
            std::string::npos)
      << objects->fallbacks[1];
  const auto draws = chooseNodeDraws(scene, {});
  ASSERT_TRUE(draws) << draws.error().message;
  EXPECT_EQ(*draws, objects->draws) << "the choice alone is the bake's";
}

// Tricky: a mesh of points or lines only reaches the scene with no primitives (the loader skips
// them). It was "drawn as triangles: mesh has no triangles", after a bake attempt, and drew nothing:
// it must not be baked or counted, and the reason must say that its nodes draw nothing.
TEST(SceneObjects, AMeshWithoutPrimitivesIsNotBakedAndDrawsNothing) {
  SceneData scene = twoMeshScene();
  scene.meshes.push_back({"guides", {}});
  scene.nodes.push_back(node("guide", 2, glm::vec3(0, 30, 0)));
  const auto objects = bakeSceneObjects(scene, {}, smallBake());
  ASSERT_TRUE(objects) << objects.error().message;
  EXPECT_EQ(objects->bakes, 2) << "the cube and the slab only";
  EXPECT_FALSE(objects->meshAssets[2]);
  EXPECT_EQ(objects->draws.back(), NodeDraw::Triangles);
  ASSERT_EQ(objects->fallbacks.size(), 1u);
  EXPECT_EQ(objects->fallbacks[0], "mesh 2 'guides': no triangles to bake or draw: its nodes draw nothing");
}

// Tricky: a scene drawn as one SDF took every mesh into its one bake, see-through ones too (the
// pane hid the cube behind it). oneSdfScene makes the choice of the scene objects (the same
// function: a see-through mesh and a node whose extras ask for triangles stay triangles, a node
// asking for an SDF is baked) and takes the triangle nodes' meshes off the part to bake, the nodes
// keeping their places; a scene of see-through meshes leaves nothing to bake (empty()).
TEST(SceneObjects, AOneSdfSceneLeavesItsTriangleNodesOutOfTheBake) {
  SceneData scene = twoMeshScene();
  scene.materials.push_back({"glass", glm::vec4(0.1f, 0.3f, 0.9f, 0.3f)});
  scene.materials.back().alphaBlend = true;
  scene.meshes[1].primitives.front().material = 0;  // the slabs: glass
  scene.nodes[1].extras = R"({"hermite_sdf": {"draw": "triangles"}})";
  scene.nodes[5].extras = R"({"hermite_sdf": {"draw": "sdf"}})";
  const auto split = oneSdfScene(scene);
  ASSERT_TRUE(split) << split.error().message;
  const std::vector<int> baked = {0, -1, 0, 0, -1, 1};  // cube1 asks for triangles, slab1 for an SDF
  ASSERT_EQ(split->sdfPart.nodes.size(), scene.nodes.size());
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    EXPECT_EQ(split->sdfPart.nodes[n].mesh, baked[n]) << scene.nodes[n].name;
    EXPECT_EQ(split->sdfPart.nodes[n].world, scene.nodes[n].world) << scene.nodes[n].name;
  }
  const auto draws = chooseNodeDraws(scene, {});
  ASSERT_TRUE(draws) << draws.error().message;
  EXPECT_EQ(split->draws, *draws) << "the scene objects' choice";
  ASSERT_EQ(split->seeThrough.size(), 1u);
  EXPECT_NE(split->seeThrough[0].find("mesh 1 'slab': drawn as triangles: material 0 'glass' is alphaMode BLEND"),
            std::string::npos)
      << split->seeThrough[0];
  EXPECT_FALSE(split->empty());

  scene.nodes[5].extras.clear();
  for (NodeData& n : scene.nodes)
    if (n.mesh == 0) n.extras = R"({"hermite_sdf": {"draw": "triangles"}})";
  const auto none = oneSdfScene(scene);
  ASSERT_TRUE(none) << none.error().message;
  EXPECT_TRUE(none->empty()) << "every node draws triangles: nothing to bake";
}

// An open square (one quad, no volume: its field is positive everywhere) and a mesh whose every
// triangle has zero area (nothing left after cleaning).
MeshData openSheet(std::string name) {
  engine::scene::MeshPrimitiveData p;
  p.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  p.normals.assign(4, glm::vec3(0.0f, 1.0f, 0.0f));
  p.indices = {0, 2, 1, 0, 3, 2};
  return {std::move(name), {std::move(p)}};
}
MeshData degenerate(std::string name) {
  engine::scene::MeshPrimitiveData p;
  p.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};  // collinear
  p.normals.assign(3, glm::vec3(0.0f, 1.0f, 0.0f));
  p.indices = {0, 1, 2};
  return {std::move(name), {std::move(p)}};
}

// Tricky: a scene's leaf or decal is an open sheet, which no SDF can hold; it must not cost the
// closed meshes their SDFs. Each such mesh turns all its nodes (not only the first one, which
// triggered the bake) to triangles, is named with the reason, and is not baked again per node.
TEST(SceneObjects, MeshesThatCannotBeSdfsDrawTrianglesAndAreNamed) {
  SceneData scene = twoMeshScene();
  scene.meshes.push_back(openSheet("leaf"));
  scene.meshes.push_back(degenerate("needle"));
  for (int i = 0; i < 3; ++i) scene.nodes.push_back(node("leaf" + std::to_string(i), 2, glm::vec3(0, 5.0f * float(i), 0)));
  scene.nodes.push_back(node("needle", 3, glm::vec3(0, -5, 0)));
  const auto objects = bakeSceneObjects(scene, {}, smallBake());
  ASSERT_TRUE(objects) << objects.error().message;
  EXPECT_EQ(objects->bakes, 4) << "one bake per mesh, the failed ones included";
  ASSERT_TRUE(objects->meshAssets[0] && objects->meshAssets[1]) << "the closed meshes keep their SDFs";
  EXPECT_FALSE(objects->meshAssets[2]);
  EXPECT_FALSE(objects->meshAssets[3]);
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    EXPECT_EQ(objects->draws[n], scene.nodes[n].mesh >= 2 ? NodeDraw::Triangles : NodeDraw::Sdf) << scene.nodes[n].name;
  ASSERT_EQ(objects->fallbacks.size(), 2u);
  EXPECT_NE(objects->fallbacks[0].find("mesh 2 'leaf': drawn as triangles: mesh source: the mesh bounds no volume"),
            std::string::npos)
      << objects->fallbacks[0];
  EXPECT_NE(objects->fallbacks[1].find("mesh 3 'needle': drawn as triangles: "), std::string::npos)
      << objects->fallbacks[1];

  engine::ecs::Registry registry;
  std::vector<engine::ecs::Entity> entities;
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) entities.push_back(registry.create());
  EXPECT_EQ(addSdfInstances(scene, *objects, entities, registry).size(), 6u) << "the leaves and the needle get none";
}

// Tricky: what stops one mesh is not always about that mesh. A cancelled bake and a K that the
// budget refuses (the same K for every mesh) stop the scene with an error, not a triangle fallback.
TEST(SceneObjects, CancelAndBudgetStopTheSceneInsteadOfFallingBack) {
  const SceneData scene = twoMeshScene();
  BakeControl refuse;
  refuse.progress = [](float) { return false; };
  const auto cancelled = bakeSceneObjects(scene, {}, smallBake(), refuse);
  ASSERT_FALSE(cancelled);
  EXPECT_NE(cancelled.error().message.find("cancelled"), std::string::npos) << cancelled.error().message;
  engine::CancelToken token;
  token.cancel();
  BakeControl byToken;
  byToken.cancel = &token;
  EXPECT_FALSE(bakeSceneObjects(scene, {}, smallBake(), byToken));

  BakeSettings tooBig = smallBake();
  tooBig.budget.maxResolution = 8;
  const auto refused = bakeSceneObjects(scene, {}, tooBig);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("mesh 0 'cube': resolution 12 is over the bake budget's max resolution 8"),
            std::string::npos)
      << refused.error().message;
}

// Each bad value of each key, refused naming the node and the key (and the scene refused before any
// bake): a wrong JSON type, an unknown name, a thickness out of the tuning's range, an unknown key.
TEST(SceneObjects, BadExtrasAreRefusedNamingNodeAndKey) {
  struct Case {
    const char* extras;
    std::string expected;
  };
  const Case cases[] = {
      {R"({"hermite_sdf": {"draw": "mesh"}})", "extras.hermite_sdf.draw: 'mesh' is not one of sdf, triangles"},
      {R"({"hermite_sdf": {"draw": 1}})", "extras.hermite_sdf.draw is a JSON number, not a string"},
      {R"({"hermite_sdf": {"draw": "sdf", "colour": "red"}})", "extras.hermite_sdf.colour: unknown key (known: draw, shell)"},
      {R"({"hermite_sdf": "triangles"})", "extras.hermite_sdf is a JSON string, not an object"},
      {R"({"hermite_sdf": {"shell": "thick"}})", "extras.hermite_sdf.shell is a JSON string, not a number"},
      {R"({"hermite_sdf": {"shell": -0.1}})", "extras.hermite_sdf.shell: -0.1 is not between 0 and 1e+06"},
      {R"({"hermite_sdf": {"shell": 2e6}})", "extras.hermite_sdf.shell: 2e+06 is not between 0 and 1e+06"},
  };
  for (const Case& c : cases) {
    SceneData scene = twoMeshScene();
    scene.nodes[3].extras = c.extras;
    const std::string message = errorOf(scene);
    EXPECT_NE(message.find("node 'cube3'"), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
    EXPECT_FALSE(bakeSceneObjects(scene, {}, smallBake())) << c.extras << ": refused before any bake";
  }
}

// A unit square in the z = 0 plane: it bounds no volume, so it bakes only as a shell.
MeshData sheetMesh(std::string name) {
  engine::scene::MeshPrimitiveData p;
  p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  p.normals.assign(4, glm::vec3(0.0f, 0.0f, 1.0f));
  p.indices = {0, 1, 2, 2, 1, 3};
  return {std::move(name), {std::move(p)}};
}

// The cube (-1..1) placed twice and the sheet once.
SceneData solidAndSheetScene() {
  SceneData scene;
  scene.meshes.push_back(boxMesh("cube", glm::vec3(-1.0f), glm::vec3(1.0f)));
  scene.meshes.push_back(sheetMesh("leaf"));
  scene.nodes.push_back(node("cube0", 0, glm::vec3(0.0f)));
  scene.nodes.push_back(node("cube1", 0, glm::vec3(5.0f, 0.0f, 0.0f)));
  scene.nodes.push_back(node("leaf", 1, glm::vec3(0.0f, 3.0f, 0.0f)));
  return scene;
}

// Tricky: a scene of solids and sheets. One thickness for the whole scene either leaves the sheets
// as triangles (0: they bound no volume) or hollows and inflates every solid by half of it, so the
// node names its mesh's own thickness, which wins over the settings' both ways: the leaf is a shell
// with the settings at 0, and the cubes stay solid with the settings' shell. The bounds tell: a
// shell's grow by half its thickness off the triangles. The levels of detail bake each mesh as the
// scene's bake did (a leaf level baked without its shell is refused: bounds no volume).
TEST(SceneObjects, ANodesOwnShellThicknessWinsOverTheSettings) {
  SceneData scene = solidAndSheetScene();
  BakeSettings settings = smallBake();
  settings.resolution = 16;
  const auto solids = bakeSceneObjects(scene, {}, settings);
  ASSERT_TRUE(solids) << solids.error().message;
  EXPECT_FALSE(solids->meshAssets[1]) << "a sheet without a shell draws its triangles";
  EXPECT_EQ(solids->fallbacks.size(), 1u);

  scene.nodes[2].extras = R"({"hermite_sdf": {"shell": 0.2}})";
  const auto leafShell = bakeSceneObjects(scene, {}, settings);
  ASSERT_TRUE(leafShell) << leafShell.error().message;
  ASSERT_TRUE(leafShell->meshAssets[0] && leafShell->meshAssets[1]) << "both meshes are SDFs";
  EXPECT_TRUE(leafShell->fallbacks.empty());
  EXPECT_EQ(leafShell->meshShells, (std::vector<double>{0.0, 0.2}));
  EXPECT_NEAR(leafShell->meshAssets[0]->surfaceBounds.max.x, 1.0, 1e-5) << "the cube is solid";
  EXPECT_NEAR(leafShell->meshAssets[1]->surfaceBounds.max.z, 0.1, 1e-5) << "the leaf is a shell 0.2 thick";
  const auto levels = bakeSceneObjectLevels(scene, *leafShell, settings, 8);
  ASSERT_TRUE(levels) << levels.error().message;
  ASSERT_EQ((*levels)[1].size(), 2u) << "K = 16 and 8";
  EXPECT_NEAR((*levels)[1][1]->surfaceBounds.max.z, 0.1, 1e-5);

  settings.shellThickness = 0.3;
  scene.nodes[0].extras = R"({"hermite_sdf": {"shell": 0}})";
  scene.nodes[2].extras.clear();
  const auto cubeSolid = bakeSceneObjects(scene, {}, settings);
  ASSERT_TRUE(cubeSolid) << cubeSolid.error().message;
  EXPECT_EQ(cubeSolid->meshShells, (std::vector<double>{0.0, 0.3}));
  EXPECT_NEAR(cubeSolid->meshAssets[0]->surfaceBounds.max.x, 1.0, 1e-5) << "cube0's 0 holds for cube1 too";
  EXPECT_NEAR(cubeSolid->meshAssets[1]->surfaceBounds.max.z, 0.15, 1e-5) << "the settings' shell";
}

// Tricky: one mesh is one asset, so two of its nodes naming two thicknesses cannot both be drawn;
// the refusal names both nodes and values. Nodes that agree, or a triangle node's value (nothing of
// it is baked), are not a conflict.
TEST(SceneObjects, NodesOfOneMeshNamingTwoShellThicknessesAreRefusedNamingBoth) {
  SceneData scene = solidAndSheetScene();
  scene.nodes[0].extras = R"({"hermite_sdf": {"shell": 0.1}})";
  scene.nodes[1].extras = R"({"hermite_sdf": {"shell": 0.2}})";
  const auto refused = bakeSceneObjects(scene, {}, smallBake());
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find(
                "mesh 0 'cube': node 'cube0' asks for extras.hermite_sdf.shell 0.1 and node 'cube1' for 0.2"),
            std::string::npos)
      << refused.error().message;

  scene.nodes[1].extras = R"({"hermite_sdf": {"shell": 0.2, "draw": "triangles"}})";
  const auto oneSdf = bakeSceneObjects(scene, {}, smallBake());
  ASSERT_TRUE(oneSdf) << oneSdf.error().message;
  EXPECT_DOUBLE_EQ(oneSdf->meshShells[0], 0.1);
  scene.nodes[1].extras = R"({"hermite_sdf": {"shell": 0.1}})";
  EXPECT_TRUE(bakeSceneObjects(scene, {}, smallBake()));
}

TEST(SceneObjects, UnknownTriangleNodeNameIsRefusedByName) {
  SceneObjectOptions options;
  options.triangleNodes = {"cube0", "kube9"};
  const std::string message = errorOf(twoMeshScene(), options);
  EXPECT_NE(message.find("no node named 'kube9'"), std::string::npos) << message;
}

// Tricky: levels are per mesh, not per node: instances of one mesh share the same level assets
// (level 0 is the asset the scene's bake made, not a second bake), yet each instance picks its own
// level from its own distance, so near and far copies of one mesh draw different K in one frame.
TEST(SceneObjects, InstancesShareTheirMeshsLevelsAndChooseTheirOwn) {
  SceneData scene = twoMeshScene();
  scene.nodes[3] = node("cube3", 0, glm::vec3(0.0f, 0.0f, -400.0f));  // one cube far down the view
  BakeSettings settings = smallBake();
  settings.resolution = 32;
  SceneObjectOptions options;
  options.triangleNodes = {"slab1"};
  const auto objects = bakeSceneObjects(scene, options, settings);
  ASSERT_TRUE(objects) << objects.error().message;
  const auto levels = bakeSceneObjectLevels(scene, *objects, settings, 8);
  ASSERT_TRUE(levels) << levels.error().message;
  ASSERT_EQ(levels->size(), 2u);
  for (std::size_t mesh = 0; mesh < 2; ++mesh) {
    const auto& mine = (*levels)[mesh];
    ASSERT_EQ(mine.size(), 3u) << "K = 32, 16, 8 for mesh " << mesh;
    EXPECT_EQ(mine.front().get(), objects->meshAssets[mesh].get()) << "level 0 is the scene's own bake";
    for (std::size_t l = 0; l < mine.size(); ++l) EXPECT_EQ(mine[l]->cells.grid.resolution, 32 >> l);
  }

  engine::ecs::Registry registry;
  std::vector<engine::ecs::Entity> entities;
  for (const NodeData& n : scene.nodes) {
    const engine::ecs::Entity e = registry.create();
    registry.emplace<engine::scene::WorldTransform>(e, engine::scene::WorldTransform{n.world});
    entities.push_back(e);
  }
  addSdfInstances(scene, *objects, entities, registry);
  EXPECT_EQ(addSdfInstanceLevels(scene, *objects, *levels, entities, 2.0f, registry), 5u) << "slab1 draws triangles";
  EXPECT_FALSE(registry.has<HermiteSdfLod>(entities[5]));
  EXPECT_EQ(registry.get<HermiteSdfLod>(entities[0]).levels, registry.get<HermiteSdfLod>(entities[1]).levels);
  EXPECT_EQ(registry.get<HermiteSdfLod>(entities[4]).levels, (*levels)[1]);

  // The eye 12 units in front of cube0 (the first cube, 2 units across): cube0 fills much of a
  // 1080-pixel image and keeps K = 32; cube3, 400 units away, covers a few pixels and draws K = 8.
  const auto camera = engine::render::CameraView::lookAt({0, 0, 12}, {0, 0, 0}, 0.8f, 0.05f, 16.0f / 9.0f);
  selectSdfLevels(registry, camera, 1080);
  EXPECT_EQ(registry.get<HermiteSdfRenderable>(entities[0]).asset->cells.grid.resolution, 32);
  EXPECT_EQ(registry.get<HermiteSdfRenderable>(entities[3]).asset->cells.grid.resolution, 8);
}

// The committed sample scene: several meshes, 100+ instances, some marked as triangles in extras.
TEST(SceneObjects, SampleGridSceneChoices) {
  const auto scene = engine::scene::loadGltf(std::filesystem::path(HSDF_ASSET_DIR) / "grid_scene.glb");
  ASSERT_TRUE(scene) << scene.error().message;
  EXPECT_EQ(scene->meshes.size(), 4u);
  const auto draws = chooseNodeDraws(*scene, {});
  ASSERT_TRUE(draws) << draws.error().message;
  int sdf = 0, triangles = 0;
  for (std::size_t n = 0; n < scene->nodes.size(); ++n) {
    if (scene->nodes[n].mesh < 0) continue;
    ((*draws)[n] == NodeDraw::Sdf ? sdf : triangles) += 1;
  }
  EXPECT_EQ(sdf + triangles, 120);
  EXPECT_EQ(triangles, 12);
  EXPECT_GE(sdf, 100) << "the sample scene is meant to hold 100+ SDF instances";
}

}  // namespace
}  // namespace hsdf
