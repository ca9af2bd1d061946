#version 450 core
// Depth from a directional light (core/render/shadow_maps.cpp).

layout(location = 0) in vec3 a_position;

uniform mat4 u_light_view_projection;

void main() { gl_Position = u_light_view_projection * vec4(a_position, 1.0); }
