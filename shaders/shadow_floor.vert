#version 330 core
// The patch of ground the shadow map covers (the light's view, projected down onto y = 0): two
// triangles from four corners. Only there can the floor be in shadow, so only there is it drawn.
uniform mat4 u_view_proj;
uniform vec3 u_corners[4];  // metres, on the ground, in order around the patch

out vec3 v_world;

#include "shadow_coord.glsl"

void main() {
  int corner[6] = int[6](0, 1, 2, 0, 2, 3);
  v_world = u_corners[corner[gl_VertexID]];
  shadowCoord(v_world, vec3(0.0, 1.0, 0.0));
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
