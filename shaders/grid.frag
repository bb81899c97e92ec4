#version 330 core
// Anti-aliased grid lines every 10 cm (faint), 1 m, and the X (red) and Z (blue) axes, over a
// slightly lighter floor; everything fades with distance (distances scale with the camera's, so
// a large scene's floor does not vanish). Shadows are laid over it by shadow_floor.frag.
in vec3 v_world;

uniform vec3 u_eye;
uniform vec3 u_background;
uniform float u_fade_scale;  // 1 at a character's framing distance, more when the camera is farther

out vec4 out_color;

float lines(vec2 p, float spacing, float width_px) {
  vec2 q = p / spacing;
  vec2 d = fwidth(q);
  vec2 g = abs(fract(q - 0.5) - 0.5) / max(d, vec2(1e-6));
  return 1.0 - min(min(g.x, g.y) / width_px, 1.0);
}

void main() {
  vec2 p = v_world.xz;
  float dist = length(u_eye - v_world) / u_fade_scale;
  float minor = lines(p, 0.1, 1.0) * 0.10 * clamp(1.0 - dist / 12.0, 0.0, 1.0);
  float major = lines(p, 1.0, 1.2) * 0.32;
  vec3 color = vec3(0.58, 0.60, 0.64);
  float alpha = max(minor, major);
  vec2 d = fwidth(p);
  float x_axis = 1.0 - min(abs(p.y) / max(d.y, 1e-6) / 1.5, 1.0);
  float z_axis = 1.0 - min(abs(p.x) / max(d.x, 1e-6) / 1.5, 1.0);
  if (x_axis > 0.0) { color = mix(color, vec3(0.85, 0.32, 0.30), x_axis); alpha = max(alpha, 0.7 * x_axis); }
  if (z_axis > 0.0) { color = mix(color, vec3(0.30, 0.50, 0.90), z_axis); alpha = max(alpha, 0.7 * z_axis); }
  // The floor itself: a touch lighter than the background near the camera.
  float near = clamp(1.0 - dist / 40.0, 0.0, 1.0);
  vec3 floor_color = u_background * 1.25;
  float fade = clamp(1.0 - dist / 45.0, 0.0, 1.0);
  vec3 rgb = mix(floor_color, color, alpha);
  out_color = vec4(rgb, fade * max(0.55 * near, alpha));
}
