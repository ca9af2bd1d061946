// A yarn segment as the lumislice renderer draws it (core/render/lumislice_renderer.h
// LumisliceSegment, std430): its ends, the section's turn at each, the transported
// normal at its start, its yarn's radius, and the planes that bisect its joints with
// its neighbours, between which its part of the yarn lies.

struct Segment {
  vec4 start;        // xyz, w: turn (radians)
  vec4 end;          // xyz, w: turn
  vec4 normal;       // xyz: unit normal at the start, w: yarn radius (world units)
  vec4 start_plane;  // xyz: unit normal of the bisector at the start (along the yarn), w: LOD level
  vec4 end_plane;    // xyz: unit normal of the bisector at the end, w: yarn (lumislice index)
};

layout(std430, binding = 0) readonly buffer Segments { Segment segments[]; };

uniform float u_extent[16];  // per yarn: the section's extent, yarn radii

struct SegmentFrame {
  vec3 origin, t, n, b;
  float length, radius, reach;  // reach: the section's extent, world units
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
  f.reach = u_extent[int(s.end_plane.w)] * f.radius;
  return f;
}
