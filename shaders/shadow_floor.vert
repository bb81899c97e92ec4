#version 330 core
// The patch of ground shadows can fall on (the casters' box projected down along the light): a
// convex polygon drawn as a triangle fan. Only there is the floor's shadow looked up.
uniform mat4 u_view_proj;
uniform vec3 u_corners[8];  // metres, on the ground, in order around the patch

out vec3 v_world;

#include "shadow_coord.glsl"

void main() {
  v_world = u_corners[gl_VertexID];
  shadowCoord(v_world, vec3(0.0, 1.0, 0.0));
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
