#version 460
// Mesh shading, depth EQUAL after the prepass. Compiled a second time as mesh_blended.frag
// (HSDF_MESH_BLENDED, shaders/CMakeLists.txt): the transparent pass's meshes (glTF alphaMode
// BLEND), lit by this same code, write their alpha for the pipeline's blending.
// Each is compiled in three material variants (MeshFeature picks one per draw): this whole source,
// for a material with a normal texture; HSDF_MESH_NO_NORMAL_MAP (mesh_textured.frag), without the
// normal texture's frame and read; HSDF_MESH_UNTEXTURED (mesh_untextured.frag), which reads no
// texture at all (each would read set 0's white texel: 1.0, its factor unchanged). The cheaper
// ones hold fewer live values (docs/perf/render-changes-session42.md), and draw the same pixels.
#extension GL_GOOGLE_include_directive : require
#include "shared/host_device.h"
#include "shared/lighting.glsl"

layout(push_constant, scalar) uniform Push { DrawPushConstants pc; };

layout(location = 0) in vec3 inWorldPosition;
layout(location = 1) in vec3 inWorldNormal;
layout(location = 2) flat in uint inObject;
layout(location = 3) in vec2 inTexcoord;

// The object's material textures (engine::render::MeshTextures: a white texel for each it lacks,
// which leaves its factor as it is). The colours are sRGB images, read as linear colour; the
// metallic-roughness and occlusion ones are linear data.
#ifdef HSDF_MESH_UNTEXTURED
#define HSDF_MESH_NO_NORMAL_MAP 1
#define MATERIAL_TEXEL(sampler) vec4(1.0)  // the white texel every kind of set 0 holds
#else
layout(set = 0, binding = MESH_TEXTURE_BASE_COLOR) uniform sampler2D baseColorTexture;
layout(set = 0, binding = MESH_TEXTURE_METALLIC_ROUGHNESS) uniform sampler2D metallicRoughnessTexture;
layout(set = 0, binding = MESH_TEXTURE_OCCLUSION) uniform sampler2D occlusionTexture;
layout(set = 0, binding = MESH_TEXTURE_EMISSIVE) uniform sampler2D emissiveTexture;
#define MATERIAL_TEXEL(sampler) texture(sampler, inTexcoord)
#endif
#ifndef HSDF_MESH_NO_NORMAL_MAP
layout(set = 0, binding = MESH_TEXTURE_NORMAL) uniform sampler2D normalTexture;
layout(location = 4) in vec4 inWorldTangent;  // mesh.vert: 0 for a mesh without TANGENT
#endif

layout(location = 0) out vec4 outColor;

#ifndef HSDF_MESH_NO_NORMAL_MAP
// The frame of the mesh's TANGENT attribute at this pixel (glTF: the bitangent is cross(normal,
// tangent) * w, toward -v), the tangent made perpendicular to `n`; false when the mesh has none (0)
// or it is parallel to n, so that the caller falls back to the derivative frame.
bool tangentFrame(vec3 n, out vec3 t, out vec3 b) {
  vec3 across = inWorldTangent.xyz - n * dot(n, inWorldTangent.xyz);
  float length2 = dot(across, across);
  if (!(length2 > 1e-24)) return false;
  t = across * inversesqrt(length2);
  b = cross(n, t) * (inWorldTangent.w < 0.0 ? -1.0 : 1.0);
  return true;
}

// glTF normalTexture: `n` (the unit vertex normal of the front face) tilted by the texel's normal,
// its x and y times `scale`, in the surface's tangent frame at this pixel: the tangent toward +u,
// the bitangent toward -v (glTF's v runs down the image, its normal maps' green up). The frame is
// the mesh's TANGENT attribute when it has one (tangentFrame: a baker's MikkTSpace tangents, which
// its normal maps were made in). Without, it comes from the screen-space derivatives of the position
// and the texture coordinates (the cotangent frame): it follows the texture's real directions on
// the triangle, so mirrored texture coordinates and mirrored instances need no handedness. Its sign
// is the screen's: Vulkan's y runs down, which turns the cross products round. The derivatives
// (dpx, dpy of the position, duvx, duvy of the texture coordinates) are taken by the caller
// outside any branch (they need the whole quad); the texture is read with them (textureGrad), so
// that this may run in a branch that meshes without a normal texture skip.
vec3 normalMapped(vec3 n, float scale, vec3 dpx, vec3 dpy, vec2 duvx, vec2 duvy) {
  vec3 m = textureGrad(normalTexture, inTexcoord, duvx, duvy).xyz * 2.0 - 1.0;
  vec3 tangent, bitangent;
  if (tangentFrame(n, tangent, bitangent))
    return normalize(tangent * (m.x * scale) + bitangent * (m.y * scale) + n * m.z);
  vec3 dpyPerp = cross(dpy, n), dpxPerp = cross(n, dpx);
  vec3 t = dpyPerp * duvx.x + dpxPerp * duvy.x;  // along +u
  vec3 b = dpyPerp * duvx.y + dpxPerp * duvy.y;  // along +v
  float side = dot(cross(dpx, dpy), n) < 0.0 ? -1.0 : 1.0;
  float frameScale = side * inversesqrt(max(max(dot(t, t), dot(b, b)), 1e-30));
  return normalize((t * (m.x * scale) - b * (m.y * scale)) * frameScale + n * m.z);
}
#endif

void main() {
  FrameGlobals frame = FrameGlobalsRef(pc.frameGlobals).globals;
  ObjectData object = ObjectsRef(pc.objects).objects[inObject];
  // The rasterizer says which side of the triangle the eye sees (front faces as the pipeline's
  // front-face state says: clockwise for a mirrored object, whose matrix reverses the winding). A
  // back face is only drawn for a double-sided mesh (glTF doubleSided: "the back-face MUST have its
  // normals reversed before the lighting equation is evaluated"): its normal is reversed, here and
  // in the normals view.
  // The normal texture tilts the front face's normal; a back face's is that one reversed.
  vec3 n = normalize(inWorldNormal);
#ifndef HSDF_MESH_NO_NORMAL_MAP
  vec3 dpx = dFdx(inWorldPosition), dpy = dFdy(inWorldPosition);
  vec2 duvx = dFdx(inTexcoord), duvy = dFdy(inTexcoord);
  // 0: no normal texture, the vertex normal as it was (a draw with a normal texture of scale 0).
  if (object.emission.a != 0.0) n = normalMapped(n, object.emission.a, dpx, dpy, duvx, duvy);
#endif
  if (!gl_FrontFacing) n = -n;
  vec3 color;
  float alpha = 1.0;
  if (pc.debugView == DEBUG_VIEW_NORMALS) {
    color = debugNormalColor(n);
  } else if (pc.debugView == DEBUG_VIEW_DEPTH) {
    color = vec3(gl_FragCoord.z);
  } else {
    // On the side seen, the interpolated vertex normal may still face away near a silhouette (the
    // vertices' normals lean over it): bent to face the eye, not turned round, which lit single
    // pixels along the outline as the object's far side.
    n = normalTowardEye(n, towardViewer(frame, inWorldPosition));
    // glTF: the base colour is the factor times the texture, its alpha too; the roughness is the
    // factor times the metallic-roughness texture's green. Its blue (the metallic) is not read:
    // the lighting shared with the SDF objects has no metallic term, for the factor neither.
    vec4 baseColor = object.color * MATERIAL_TEXEL(baseColorTexture);
    float roughness = object.material.x * MATERIAL_TEXEL(metallicRoughnessTexture).g;
    // glTF occlusionTexture: 1 + strength * (red - 1) of the ambient light reaches the surface.
    float occlusion = 1.0 + object.material.w * (MATERIAL_TEXEL(occlusionTexture).r - 1.0);
    // Emission (glTF emissiveFactor times emissiveTexture) is light of the surface's own: added
    // after the lighting, so a face turned from the light still shows it.
    vec3 emission = object.emission.rgb * MATERIAL_TEXEL(emissiveTexture).rgb;
    color = shadeOccludedSurface(frame, baseColor.rgb, roughness, occlusion, inWorldPosition, n) + emission;
    alpha = baseColor.a;
  }
#ifdef HSDF_MESH_BLENDED
  // Straight alpha, as glTF's base colour is: the pipeline's blending multiplies the colour by it
  // (the "over" operator glTF asks for, emission included); the normals and depth views draw no
  // blended mesh (MeshFeature).
  outColor = vec4(color, alpha);
#else
  outColor = vec4(color, 1.0);  // opaque whatever the alpha (glTF OPAQUE ignores it)
#endif
}
