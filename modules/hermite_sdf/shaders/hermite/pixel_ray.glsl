// The direction of this fragment's ray, rebuilt from gl_FragCoord: the offset from the eye to the
// pixel centre unprojected at the fragment's own depth gl_FragCoord.z, in the grid units (object
// space / spacing) of the object whose inverse model matrix is `invModel`. With the eye as origin,
// the ray u(t) = eye + t * direction reaches this fragment's point on the rasterized face at t = 1;
// view distance is linear in t, so a point at t has reverse-Z depth gl_FragCoord.z / t and the near
// plane lies at t = gl_FragCoord.z. The direction is a view-space offset rotated into the grid,
// never a difference of two far points.
//
// Why not interpolate the face point from the vertices: an NVIDIA H200 interpolates varyings less
// precisely than lavapipe, and the depth of every hit on a ray built from an interpolated face point
// and a flat eye was 10-20x further from the reference there (median 1e-4 cells at K = 64, the
// roots tests' boxes lost pixels), while the bricks, which rebuilt their rays like this, matched
// lavapipe's 1e-6 (docs/gpu-vs-lavapipe.md). The viewport is the whole frame (FrameGlobals).
vec3 pixelRayDirection(FrameGlobals frame, mat4 invModel, float spacing) {
  vec2 ndc = gl_FragCoord.xy * frame.viewport.zw * 2.0 - 1.0;
  vec4 face = frame.invProj * vec4(ndc, gl_FragCoord.z, 1.0);  // view space, eye at 0
  vec3 toFace = mat3(frame.invView) * (face.xyz / face.w);
  return mat3(invModel) * toFace / spacing;
}
