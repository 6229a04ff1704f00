// Shading shared by every surface kind, so that meshes and SDF objects look alike.
#ifndef HSDF_LIGHTING_GLSL
#define HSDF_LIGHTING_GLSL

// The unit vector from worldPosition towards the viewer: to the eye point (perspective), or the
// view's own direction (orthographic), from the homogeneous eye of FrameGlobals::cameraPosition.
vec3 towardViewer(FrameGlobals frame, vec3 worldPosition) {
  return normalize(frame.cameraPosition.xyz - worldPosition * frame.cameraPosition.w);
}

// How far a shading normal that must face the eye is bent past perpendicular (cosine).
const float kFacingEyeCosine = 1e-3;

// `n` (unit) bent in the plane of n and v (unit, towards the eye) until it just faces the eye, if it
// faces away. For a surface known to face the eye whose shading normal does not: a vertex normal
// interpolated over a front face near a silhouette, a sphere tracer's hit at a ray's closest
// approach to a surface it grazes. Bending keeps the normal's direction across the view; turning
// it round (-n) would light it as the far side of the object (bright or dark specks).
vec3 normalTowardEye(vec3 n, vec3 v) {
  float nv = dot(n, v);
  if (nv >= kFacingEyeCosine) return n;
  vec3 across = n - nv * v;  // the part perpendicular to v
  float len = length(across);
  if (len < 1e-6) return v;  // n was (anti)parallel to v: no direction across the view to keep
  return normalize(across / len + kFacingEyeCosine * v);
}

// Lambert + Blinn-Phong with a hemispheric ambient term; all in linear colour. A normal that
// faces away from the eye is a back face (the inside of an SDF object seen from within it, or
// through the near plane): it is lit as its other side. Callers that know their surface faces the
// eye bend a normal that does not with normalTowardEye first (mesh.frag, the sphere tracers).
// `occlusion` is the part of the ambient light that reaches the surface (glTF occlusionTexture:
// the direct light is not occluded); 1 for shadeSurface.
vec3 shadeOccludedSurface(FrameGlobals frame, vec3 baseColor, float roughness, float occlusion, vec3 worldPosition,
                          vec3 normal) {
  vec3 n = normalize(normal);
  vec3 v = towardViewer(frame, worldPosition);
  if (dot(n, v) < 0.0) n = -n;
  vec3 l = normalize(frame.lightDirection.xyz);
  vec3 h = normalize(l + v);
  float diffuse = max(dot(n, l), 0.0);
  float shininess = mix(128.0, 8.0, clamp(roughness, 0.0, 1.0));
  float specular = pow(max(dot(n, h), 0.0), shininess) * (1.0 - roughness) * 0.5;
  float ambient = frame.lightColor.a * (0.6 + 0.4 * n.y) * occlusion;
  vec3 light = frame.lightColor.rgb * frame.lightDirection.w;
  return baseColor * (ambient + diffuse * light) + specular * light;
}

vec3 shadeSurface(FrameGlobals frame, vec3 baseColor, float roughness, vec3 worldPosition, vec3 normal) {
  return shadeOccludedSurface(frame, baseColor, roughness, 1.0, worldPosition, normal);
}

vec3 debugNormalColor(vec3 normal) { return normalize(normal) * 0.5 + 0.5; }

#endif
