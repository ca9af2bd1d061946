#version 450 core
// Test scene: Lambert + Blinn-Phong under one directional light, with a two-colour
// pattern from the uvs (checks where both scales are set, stripes along u otherwise).
// Writes linear radiance.

in vec3 v_world_position;
in vec3 v_world_normal;
in vec2 v_uv;

uniform vec3 u_eye;
uniform vec3 u_light_direction;  // towards the light, normalised
uniform vec3 u_light_radiance;
uniform vec3 u_ambient;
uniform vec4 u_pattern_scale;    // xy: pattern repeats along u and v (0 = none)
uniform vec3 u_colour_a;
uniform vec3 u_colour_b;

layout(location = 0) out vec4 o_radiance;

void main() {
  vec2 cell = floor(v_uv * u_pattern_scale.xy);
  bool a = mod(cell.x + cell.y, 2.0) < 0.5;
  vec3 albedo = a ? u_colour_a : u_colour_b;

  vec3 n = normalize(v_world_normal);
  vec3 v = normalize(u_eye - v_world_position);
  vec3 h = normalize(u_light_direction + v);
  float n_dot_l = max(dot(n, u_light_direction), 0.0);
  const float kPi = 3.14159265358979;
  float specular = n_dot_l > 0.0 ? 0.04 * (64.0 + 8.0) / (8.0 * kPi) * pow(max(dot(n, h), 0.0), 64.0) : 0.0;
  vec3 radiance = u_ambient * albedo + u_light_radiance * n_dot_l * (albedo / kPi + vec3(specular));
  o_radiance = vec4(radiance, 1.0);
}
