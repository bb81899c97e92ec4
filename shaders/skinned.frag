#version 330 core
// A skinned mesh: its base colour (factor times texture) under the shared lighting. Both sides
// are lit (glTF meshes are often single-sided shells seen from inside at the mouth or ears).
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

#include "lighting.glsl"

uniform sampler2D u_base_texture;
uniform vec4 u_base_color;  // glTF baseColorFactor
uniform float u_textured;   // 1: multiply by the texture

out vec4 out_color;

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec4 albedo = u_base_color;
  if (u_textured > 0.5) albedo *= texture(u_base_texture, v_uv);
  out_color = vec4(shade(albedo.rgb, n, v_world, 0.12), 1.0);
}
