// Shared by the lit fragment shaders (the renderer expands `#include "lighting.glsl"` in place):
// the key light with its shadow map, sky/ground ambient, a soft rim, distance fog. The renderer
// compiles each lit shader twice, with SINEW_SHADOWS 1 and 0: Mesa's llvmpipe runs both sides of
// a branch, so a uniform "shadows off" switch would still pay for every shadow tap.

uniform vec3 u_eye;            // camera position, metres
uniform vec3 u_light_dir;      // towards the key light, unit
uniform vec3 u_background;     // what the fog fades into
uniform float u_fog_start;     // metres from the eye where fog begins
uniform float u_fog_range;     // metres over which it thickens to the background

float fogAmount(vec3 world) {
  return clamp((length(u_eye - world) - u_fog_start) / u_fog_range, 0.0, 1.0);
}

#if SINEW_SHADOWS
uniform sampler2DShadow u_shadow_map;  // depth from the key light, compared in hardware (2x2)
uniform float u_shadow_size;           // shadow-map texels across

in vec3 v_shadow;  // from shadowCoord (shadow_coord.glsl) in the vertex shader

// How much of the key light reaches this fragment (0 shadowed .. 1 lit). One filtered tap (a
// 2 x 2 comparison) on the characters themselves, where a crisp edge is right and llvmpipe's cost
// per pixel counts; four a texel either side (an edge about four texels wide) where the shader
// defines SINEW_SOFT_SHADOW first: the floor, where the shadow is read as the character's contact.
float keyVisibility() {
  vec3 s = v_shadow;
  if (s.x <= 0.0 || s.y <= 0.0 || s.x >= 1.0 || s.y >= 1.0 || s.z >= 1.0) return 1.0;
  s.z -= 0.0005;
#ifdef SINEW_SOFT_SHADOW
  float d = 1.0 / u_shadow_size;
  return 0.25 * (texture(u_shadow_map, vec3(s.xy + vec2(-d, -d), s.z)) +
                 texture(u_shadow_map, vec3(s.xy + vec2(d, -d), s.z)) +
                 texture(u_shadow_map, vec3(s.xy + vec2(-d, d), s.z)) +
                 texture(u_shadow_map, vec3(s.xy + vec2(d, d), s.z)));
#else
  return texture(u_shadow_map, s);
#endif
}
#else
float keyVisibility() { return 1.0; }
#endif

// The colour of a lit surface: `albedo` under the key light (shadowed), a sky/ground hemisphere
// ambient, a highlight of strength `shine`, a rim; then fog, and the editor's mild display curve.
vec3 shade(vec3 albedo, vec3 n, vec3 world, float shine) {
  vec3 v = normalize(u_eye - world);
  float ndl = dot(n, u_light_dir);
  float key = max(ndl, 0.0);
  // Near the terminator the key is already fading: the shadow test fades in with it instead of
  // flickering where the surface turns from the light.
  float visible = mix(1.0, keyVisibility(), smoothstep(0.0, 0.15, ndl));
  float sky = 0.5 + 0.5 * n.y;
  vec3 ambient = mix(vec3(0.16, 0.15, 0.14), vec3(0.34, 0.37, 0.42), sky);
  vec3 h = normalize(u_light_dir + v);
  float spec = pow(max(dot(n, h), 0.0), 40.0) * shine * visible;
  float rim = pow(1.0 - max(dot(n, v), 0.0), 3.0) * 0.18;
  vec3 lit = albedo * (ambient + vec3(1.0, 0.97, 0.92) * key * 0.85 * visible) + vec3(spec + rim);
  lit = mix(lit, u_background, fogAmount(world));
  return pow(lit, vec3(1.0 / 1.15));
}
