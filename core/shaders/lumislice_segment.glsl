// A yarn segment as the lumislice renderer draws it (core/render/lumislice_renderer.h
// LumisliceSegment, std430): its ends, the section's turn at each, the transported
// normal at its start, its yarn's radius, and the planes that bisect its joints with
// its neighbours, between which its part of the yarn lies. A yarn narrower than a pixel
// is drawn as a pixel-wide yarn whose section is the true one stretched (the optical
// depth along a ray kept, as the density is per yarn radius) and whose radiance and
// opacity are scaled by the coverage: the pixel's mean, without one ray's aliasing.

struct Segment {
  vec4 start;        // xyz, w: turn (radians)
  vec4 end;          // xyz, w: turn
  vec4 normal;       // xyz: unit normal at the start, w: the yarn's radius as drawn (world units)
  vec4 start_plane;  // xyz: unit normal of the bisector at the start (along the yarn)
  vec4 end_plane;    // xyz: unit normal of the bisector at the end
  vec4 shading;      // x: coverage, the yarn's radius over the radius drawn (a sub-pixel yarn
                     // is widened); y: LOD level; z: yarn (lumislice index)
};

layout(std430, binding = 0) readonly buffer Segments { Segment segments[]; };

uniform float u_extent[16];  // per yarn: the section's extent, yarn radii

struct SegmentFrame {
  vec3 origin, t, n, b;
  float length, radius, reach;  // radius as drawn; reach: the section's extent, world units
  int yarn, level;
};

SegmentFrame FrameOf(Segment s) {
  SegmentFrame f;
  f.origin = s.start.xyz;
  vec3 d = s.end.xyz - s.start.xyz;
  f.length = max(length(d), 1e-9);
  f.t = d / f.length;
  f.n = normalize(s.normal.xyz - dot(s.normal.xyz, f.t) * f.t);
  f.b = cross(f.t, f.n);
  f.radius = s.normal.w;
  f.level = int(s.shading.y);
  f.yarn = int(s.shading.z);
  f.reach = u_extent[f.yarn] * f.radius;
  return f;
}
