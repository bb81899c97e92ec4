#version 330 core
// Linear blend skinning: each vertex is moved by the weighted sum of its four joints' skinning
// matrices (world(joint) * inverse bind, display scale included), read from a float texture.
layout(location = 0) in vec3 in_position;  // bind pose, file units
layout(location = 1) in vec3 in_normal;    // bind pose, unit
layout(location = 2) in vec2 in_uv;
layout(location = 3) in uvec4 in_joints;   // skeleton joint indices
layout(location = 4) in vec4 in_weights;   // summing to 1

uniform sampler2D u_skinning;  // RGBA32F, 4 x joints: column c of joint j's matrix at (c, j)
uniform mat4 u_view_proj;

out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
invariant gl_Position;  // the same in the depth-only and the lit programs

#include "shadow_coord.glsl"

mat4 skinMatrix(uint joint) {
  int row = int(joint);
  return mat4(texelFetch(u_skinning, ivec2(0, row), 0), texelFetch(u_skinning, ivec2(1, row), 0),
              texelFetch(u_skinning, ivec2(2, row), 0), texelFetch(u_skinning, ivec2(3, row), 0));
}

void main() {
  mat4 m = in_weights.x * skinMatrix(in_joints.x) + in_weights.y * skinMatrix(in_joints.y) +
           in_weights.z * skinMatrix(in_joints.z) + in_weights.w * skinMatrix(in_joints.w);
  vec4 world = m * vec4(in_position, 1.0);
  v_world = world.xyz;
  v_normal = mat3(m) * in_normal;  // rigid and uniformly scaled joints: normalised later
  v_uv = in_uv;
  shadowCoord(v_world, normalize(v_normal));
  gl_Position = u_view_proj * world;
}
