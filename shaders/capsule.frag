#version 330 core
// One directional key light, a sky/ground hemisphere ambient, a soft rim, and distance fog
// into the background colour.
in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;

uniform vec3 u_eye;
uniform vec3 u_light_dir;   // towards the light, unit
uniform vec3 u_background;

out vec4 out_color;

void main() {
  vec3 n = normalize(v_normal);
  vec3 v = normalize(u_eye - v_world);
  float key = max(dot(n, u_light_dir), 0.0);
  float sky = 0.5 + 0.5 * n.y;
  vec3 ambient = mix(vec3(0.16, 0.15, 0.14), vec3(0.34, 0.37, 0.42), sky);
  vec3 h = normalize(u_light_dir + v);
  float spec = pow(max(dot(n, h), 0.0), 40.0) * 0.25;
  float rim = pow(1.0 - max(dot(n, v), 0.0), 3.0) * 0.18;
  vec3 lit = v_color.rgb * (ambient + vec3(1.0, 0.97, 0.92) * key * 0.85) + vec3(spec + rim);
  float fog = clamp((length(u_eye - v_world) - 15.0) / 60.0, 0.0, 1.0);
  lit = mix(lit, u_background, fog);
  out_color = vec4(pow(lit, vec3(1.0 / 1.15)), v_color.a);
}
