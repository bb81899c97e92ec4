#version 330 core
// One capsule per instance: a unit sphere split at its equator, its halves moved to the bone's
// two ends and scaled by the radius. Y of the mesh runs along the bone.
layout(location = 0) in vec3 in_dir;     // unit direction, mesh space
layout(location = 1) in float in_end;    // 0: end a, 1: end b
layout(location = 2) in vec4 in_a_radius;  // end a (metres, world), radius (metres)
layout(location = 3) in vec3 in_b;       // end b
layout(location = 4) in vec4 in_color;   // linear RGB, opacity

uniform mat4 u_view_proj;

out vec3 v_world;
out vec3 v_normal;
out vec4 v_color;
invariant gl_Position;  // the depth-only and lit programs must place every fragment alike

#include "shadow_coord.glsl"

void main() {
  vec3 a = in_a_radius.xyz;
  vec3 axis = in_b - a;
  float len = length(axis);
  vec3 y = len > 1e-6 ? axis / len : vec3(0.0, 1.0, 0.0);
  vec3 helper = abs(y.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  vec3 x = normalize(cross(helper, y));
  vec3 z = cross(x, y);
  vec3 n = x * in_dir.x + y * in_dir.y + z * in_dir.z;
  v_world = mix(a, in_b, in_end) + n * in_a_radius.w;
  v_normal = n;
  v_color = in_color;
  shadowCoord(v_world, n);
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
