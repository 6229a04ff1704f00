// Shading pass of the sphere-tracing baselines, once per pixel: the object's box is rasterized
// again; a fragment goes on only where this object won the prepass (visibility id), rebuilds the
// hit on its pixel's ray from the offset the prepass stored (pixel_ray.glsl) and shades it with the
// normal the object asks for.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/sphere_trace_common.glsl"
#include "hermite/materials.glsl"
#include "hermite/pixel_ray.glsl"
#include "shared/debug_colors.glsl"
#include "shared/lighting.glsl"

layout(set = 0, binding = 0) uniform sampler2D sceneDepth;
layout(set = 0, binding = 1) uniform usampler2D sceneVisibility;
layout(set = 0, binding = 2) uniform sampler2D sceneHitOffset;  // pixelRayHitOffset of the winner

layout(location = 0) flat in uint inDraw;
layout(location = 0) out vec4 outColor;

void main() {
  SphereTraceDraw draw = SphereTraceDrawsRef(pc.draws).draws[inDraw];
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  uvec2 visible = texelFetch(sceneVisibility, pixel, 0).xy;
  if (visible.x != draw.object + 1u) discard;
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];

  // The hit in grid units, on the pixel's ray as the prepass based it, at the offset it stored from
  // the draw's anchor (pixelRayStoredPoint): rebuilt from the depth, through float world space and
  // the model's inverse, it was off by the depth's precision (~0.5 cell 8e6 cells out) and a float
  // ulp of the distance on each axis. In world space (eye at the origin) for the lights only.
  float depth = texelFetch(sceneDepth, pixel, 0).r;
  float offset = texelFetch(sceneHitOffset, pixel, 0).r;
  vec3 g = pixelRayStoredPoint(frame, object.invModel, draw.gridOriginSpacing.w, draw.rayAnchor, depth, offset);
  vec3 worldPosition = (frame.invView * vec4(pixelViewPoint(frame, depth), 1.0)).xyz;
  vec3 gradient = (draw.flags & HERMITE_FLAG_NORMALS_CENTRAL) != 0u ? centralFieldGradient(draw, g)
                                                                     : exactFieldGradient(draw, g);
  vec3 normal = normalize(transpose(mat3(object.invModel)) * gradient);

  vec3 color;
  if (pc.draw.debugView == DEBUG_VIEW_NORMALS) {
    color = debugNormalColor(normal);
  } else if (pc.draw.debugView == DEBUG_VIEW_DEPTH) {
    color = vec3(depth);
  } else if (pc.draw.debugView == DEBUG_VIEW_EVALS) {
    color = heat(float(visible.y & ~SPHERE_TRACE_STARTED_INSIDE) / 64.0);
  } else {
    // The tracer's hit is where its ray reached the surface from the side it started on: seen
    // from outside, the surface faces the eye there; from inside, its back faces the eye. A
    // gradient that disagrees by a little is a grazing hit (a ray stopped within epsilon just
    // past its closest approach to the surface, or the depth-rebuilt point a rounding beyond it):
    // bent to face the eye, not turned round, which shaded it as the far side (dark specks).
    // The prepass says which side the ray started on (evaluating the field again here made the
    // Hermite tracer's shading pass 27 % slower on lavapipe, even when asked only for the pixels
    // whose gradient faces away).
    vec3 n = (visible.y & SPHERE_TRACE_STARTED_INSIDE) != 0u ? -normal : normal;
    n = normalTowardEye(n, towardViewer(frame, worldPosition));
    vec3 base = object.color.rgb;
    float roughness = object.material.x;
    // A multi-material asset (payload: FieldMaterialsHeader): the entry of the nearest sample.
    if (object.payload != 0ul) applyFieldMaterial(object.payload, g, draw.resolution, base, roughness);
    color = shadeSurface(frame, base, roughness, worldPosition, n);
  }
  outColor = vec4(color, 1.0);
}
