#version 330 core
// The floor's shadow, laid over the grid: black with the shadow's strength as opacity, so it
// darkens whatever floor and lines are there; it fades with the fog.
in vec3 v_world;

#define SINEW_SOFT_SHADOW 1
#include "lighting.glsl"

uniform float u_strength;  // how dark a full shadow makes the floor, 0..1

out vec4 out_color;

void main() {
  float shadow = 1.0 - keyVisibility();
  out_color = vec4(0.0, 0.0, 0.0, u_strength * shadow * (1.0 - fogAmount(v_world)));
}
