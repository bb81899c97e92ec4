#version 330 core
// Capsules: the shared lighting (key light with shadows, sky/ground ambient, rim, fog).
in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;

#include "lighting.glsl"

out vec4 out_color;

void main() {
  out_color = vec4(shade(v_color.rgb, normalize(v_normal), v_world, 0.25), v_color.a);
}
