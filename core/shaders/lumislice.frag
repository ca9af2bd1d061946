#version 450 core
// The lumislice renderer's yarn (core/render/lumislice_renderer.h): the view ray
// through one segment's part of the yarn volume, sampled about every voxel of the
// segment's level of detail (the slices, seen parallel to the viewport), each sample's voxel
// looked up in its yarn's lumislice: density (the opacity table) at the sample's place
// in the section turned by the twist, and per light the VRF for the light's direction
// in the section's frame. Composited front to back within the segment:
//   L = Σ_k T_k α_k [ambient·ρ_d + Σ_lights E (VRF_rgb + 2ρ_s N ψ^p · VRF_a)],
//   α_k = 1 − e^{−γρ_k Δ/R},
// as the reference's march (core/acquire/volume_radiance.h). Output premultiplied
// (L, 1 − T) for back-to-front blending across segments.

#include "lights.glsl"
#include "lumislice_segment.glsl"

// Eq. 10's yarn shadow of segment s for light i at [s · u_light_count + i].
layout(std430, binding = 1) readonly buffer YarnShadows { float yarn_shadow[]; };

flat in int v_segment;
in vec3 v_position;

uniform vec3 u_eye;
uniform int u_orthographic;
uniform vec3 u_view_direction;  // orthographic cameras: the direction rays travel
uniform mat4 u_inverse_view_projection;
uniform vec2 u_frame_size;
uniform sampler2D u_opaque_depth;
uniform sampler3D u_vrf;      // x: levels side by side, y: yarns, z: directions
uniform sampler2D u_density;  // x, y as u_vrf's
uniform int u_resolution;     // of the finest level
uniform float u_optical_density;  // γ
uniform vec3 u_ambient;

uniform float u_twist_rate[16];      // per yarn: turn per yarn radius
uniform vec3 u_diffuse_albedo[16];   // per yarn
uniform vec3 u_specular_albedo[16];  // per yarn
uniform float u_specular_exponent[16];
uniform float u_specular_normalisation[16];

layout(location = 0) out vec4 o_radiance;

const int kLongitudes = 32;
const int kAltitudes = 21;
const int kLongitudeSpan = kLongitudes + 1;  // a longitude row repeats its first entry

// Voxel (x, y) (continuous, centres at + 0.5) of `level` of `yarn` in atlas texels.
vec2 AtlasTexel(int level, int yarn, vec2 voxel) {
  // Level l starts after levels 0 … l − 1, each res_k + 2 texels wide (a border each side).
  int offset = 2 * u_resolution - (2 * u_resolution >> level) + 2 * level;
  return vec2(float(offset + 1), float(yarn * (u_resolution + 2) + 1)) + voxel;
}

vec2 Rotate(vec2 p, float angle) {
  float c = cos(angle), s = sin(angle);
  return vec2(c * p.x - s * p.y, s * p.x + c * p.y);
}

void main() {
  Segment s = segments[v_segment];
  SegmentFrame f = FrameOf(s);
  int level = f.level, yarn = f.yarn;

  // The ray through this pixel, parametrised from the box's back face.
  vec3 origin = v_position;
  vec3 direction = u_orthographic != 0 ? u_view_direction : normalize(v_position - u_eye);
  float t_near = u_orthographic != 0 ? -1e30 : -distance(v_position, u_eye);
  float t_far = 0.0;
  // Inside the yarn's cylinder about the segment's axis (every sample then lies in the
  // section's disk, however few the samples) …
  vec3 local_origin = vec3(dot(origin - f.origin, f.t), dot(origin - f.origin, f.n), dot(origin - f.origin, f.b));
  vec3 local_direction = vec3(dot(direction, f.t), dot(direction, f.n), dot(direction, f.b));
  float a = dot(local_direction.yz, local_direction.yz);
  if (a < 1e-12) {
    if (dot(local_origin.yz, local_origin.yz) >= f.reach * f.reach) discard;
  } else {
    float b = dot(local_origin.yz, local_direction.yz), c = dot(local_origin.yz, local_origin.yz) - f.reach * f.reach;
    float discriminant = b * b - a * c;
    if (discriminant <= 0.0) discard;
    float root = sqrt(discriminant);
    t_near = max(t_near, (-b - root) / a);
    t_far = min(t_far, (-b + root) / a);
  }
  // … between the planes that bisect its joints …
  vec4 planes[2] = vec4[2](vec4(s.start_plane.xyz, -dot(s.start_plane.xyz, s.start.xyz)),
                           vec4(-s.end_plane.xyz, dot(s.end_plane.xyz, s.end.xyz)));
  for (int k = 0; k < 2; ++k) {
    float facing = dot(planes[k].xyz, direction), at = dot(planes[k].xyz, origin) + planes[k].w;
    if (abs(facing) < 1e-9) {
      if (at < 0.0) discard;
      continue;
    }
    float crossing = -at / facing;
    if (facing > 0.0) t_near = max(t_near, crossing); else t_far = min(t_far, crossing);
  }
  // … and in front of what is opaque.
  float depth = texelFetch(u_opaque_depth, ivec2(gl_FragCoord.xy), 0).r;
  if (depth < 1.0) {
    vec4 ndc = vec4(gl_FragCoord.xy / u_frame_size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    vec4 world = u_inverse_view_projection * ndc;
    t_far = min(t_far, dot(world.xyz / world.w - origin, direction));
  }
  if (t_near >= t_far) discard;

  int resolution = max(u_resolution >> level, 1);
  float extent = u_extent[yarn];
  float step = 2.0 * extent * f.radius / float(resolution);
  vec3 vrf_size = vec3(textureSize(u_vrf, 0));
  vec2 density_size = vec2(textureSize(u_density, 0));
  float twist = u_twist_rate[yarn] / f.radius;
  // Each light once per pixel, at the middle of the ray's way through the segment (the
  // paper tests shadows at slice vertices): its direction, its irradiance through the
  // shadow map and the yarn shadow, and its place in the VRF table but for the
  // section's turn, which each sample subtracts from the longitude.
  vec3 middle = origin + 0.5 * (t_near + t_far) * direction;
  vec3 light_direction[kMaxLights];
  vec3 light_irradiance[kMaxLights];
  float light_longitude[kMaxLights];  // at phase 0, in table entries
  float light_row[kMaxLights];        // the lower altitude row's first z texel
  float light_altitude[kMaxLights];   // the weight of the upper row
  for (int i = 0; i < u_light_count; ++i) {
    vec3 irradiance;
    vec3 l = LightDirection(i, middle, irradiance);
    light_direction[i] = l;
    light_irradiance[i] = irradiance * LightVisibility(i, middle, l) * yarn_shadow[v_segment * u_light_count + i];
    light_longitude[i] = atan(dot(l, f.b), dot(l, f.n)) / (2.0 * kPi) * float(kLongitudes);
    float altitude = (asin(clamp(dot(l, f.t), -1.0, 1.0)) / kPi + 0.5) * float(kAltitudes - 1);
    float a0 = min(floor(altitude), float(kAltitudes - 2));
    light_row[i] = a0 * float(kLongitudeSpan) + 0.5;
    light_altitude[i] = altitude - a0;
  }
  vec3 radiance = vec3(0.0);
  float transmittance = 1.0;
  // The ray's way through the segment in equal steps of at most a voxel, sampled at
  // their middles: a way shorter than a voxel (a coarse level, a short segment) still
  // gets its sample, with its own length. The count is bounded by the box's diagonal:
  // llvmpipe runs a loop until every lane of its batch is done, those outside the box too.
  float diagonal = length(vec3(f.length + 4.0 * f.reach, 2.0 * f.reach, 2.0 * f.reach));
  int count = int(clamp(ceil((t_far - t_near) / step), 1.0, ceil(diagonal / step) + 1.0));
  float h = (t_far - t_near) / float(count);
  float alpha_scale = u_optical_density * h / f.radius;
  vec3 v = -direction;
  for (int k = 0; k < count; ++k) {
    vec3 q = origin + (t_near + (float(k) + 0.5) * h) * direction;
    vec3 d = q - f.origin;
    float along = dot(d, f.t);
    float phase = mix(s.start.w, s.end.w, along / f.length);
    vec3 offset = d - along * f.t;
    // The section at phase 0 is the slice's turned back by the phase.
    vec2 section = Rotate(vec2(dot(offset, f.n), dot(offset, f.b)), -phase) / f.radius;
    if (dot(section, section) >= extent * extent) continue;
    // Kept half a voxel inside the level, so that filtering never reads its empty border
    // (at 1×1 it would dilute the one voxel by up to four).
    vec2 voxel = clamp((section / extent + 1.0) * 0.5 * float(resolution), vec2(0.5), vec2(float(resolution) - 0.5));
    vec2 texel = AtlasTexel(level, yarn, voxel);
    float rho = texture(u_density, texel / density_size).r;
    if (rho <= 0.0) continue;
    float alpha = 1.0 - exp(-rho * alpha_scale);
    vec3 fibre = normalize(f.t + twist * cross(f.t, offset));
    float cos_v = dot(fibre, v);
    vec3 light_sum = u_ambient * u_diffuse_albedo[yarn];
    vec2 xy = texel / vrf_size.xy;
    float turn = phase / (2.0 * kPi) * float(kLongitudes);
    for (int i = 0; i < u_light_count; ++i) {
      float longitude = mod(light_longitude[i] - turn, float(kLongitudes));
      float z0 = (light_row[i] + longitude) / vrf_size.z;
      vec4 vrf = mix(texture(u_vrf, vec3(xy, z0)), texture(u_vrf, vec3(xy, z0 + float(kLongitudeSpan) / vrf_size.z)),
                     light_altitude[i]);
      float cos_l = dot(fibre, light_direction[i]);
      float psi = clamp(sqrt(max(1.0 - cos_l * cos_l, 0.0)) * sqrt(max(1.0 - cos_v * cos_v, 0.0)) - cos_l * cos_v,
                        0.0, 1.0);
      vec3 specular = 2.0 * u_specular_albedo[yarn] * u_specular_normalisation[yarn] *
                      pow(psi, u_specular_exponent[yarn]) * vrf.a;
      light_sum += light_irradiance[i] * (vrf.rgb + specular);
    }
    radiance += transmittance * alpha * light_sum;
    transmittance *= 1.0 - alpha;
    if (transmittance < 0.01) {
      transmittance = 0.0;
      break;
    }
  }
  if (transmittance >= 1.0) discard;
  o_radiance = s.shading.x * vec4(radiance, 1.0 - transmittance);
}
