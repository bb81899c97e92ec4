// Shared by the vertex shaders of lit geometry (#include'd; SINEW_SHADOWS as in lighting.glsl):
// where a vertex falls in the key light's shadow map, computed per vertex so the fragment shader
// only looks the map up.

#if SINEW_SHADOWS
uniform mat4 u_light_view_proj;  // world -> the shadow map's clip space (orthographic)
uniform float u_shadow_texel;    // metres per shadow-map texel
uniform vec3 u_light_dir;        // towards the key light, unit

out vec3 v_shadow;  // shadow-map texture coordinates and depth, 0..1

// The point is pushed along its normal by about a texel (more where the light grazes) so that a
// lit surface does not shadow itself ("acne").
void shadowCoord(vec3 world, vec3 n) {
  float ndl = dot(n, u_light_dir);
  vec3 p = world + n * u_shadow_texel * (1.0 + 2.0 * (1.0 - abs(ndl)));
  v_shadow = (u_light_view_proj * vec4(p, 1.0)).xyz * 0.5 + 0.5;
}
#else
void shadowCoord(vec3 world, vec3 n) {}
#endif
