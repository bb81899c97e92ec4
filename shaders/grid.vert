#version 330 core
// A ground quad (y = 0) centred under the camera target; the grid lines are drawn per pixel.
uniform mat4 u_view_proj;
uniform vec3 u_centre;   // metres, on the ground
uniform float u_extent;  // half size, metres

out vec3 v_world;

void main() {
  vec2 corners[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
  vec2 c = corners[gl_VertexID] * u_extent;
  v_world = vec3(u_centre.x + c.x, 0.0, u_centre.z + c.y);
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
