// Shading shared by every surface kind, so that meshes and SDF objects look alike.
#ifndef HSDF_LIGHTING_GLSL
#define HSDF_LIGHTING_GLSL

// Lambert + Blinn-Phong with a hemispheric ambient term; all in linear colour.
vec3 shadeSurface(FrameGlobals frame, vec3 baseColor, float roughness, vec3 worldPosition, vec3 normal) {
  vec3 n = normalize(normal);
  vec3 v = normalize(frame.cameraPosition.xyz - worldPosition);
  if (dot(n, v) < 0.0) n = -n;  // back faces seen through clipped geometry stay lit sensibly
  vec3 l = normalize(frame.lightDirection.xyz);
  vec3 h = normalize(l + v);
  float diffuse = max(dot(n, l), 0.0);
  float shininess = mix(128.0, 8.0, clamp(roughness, 0.0, 1.0));
  float specular = pow(max(dot(n, h), 0.0), shininess) * (1.0 - roughness) * 0.5;
  float ambient = frame.lightColor.a * (0.6 + 0.4 * n.y);
  vec3 light = frame.lightColor.rgb * frame.lightDirection.w;
  return baseColor * (ambient + diffuse * light) + specular * light;
}

vec3 debugNormalColor(vec3 normal) { return normalize(normal) * 0.5 + 0.5; }

#endif
