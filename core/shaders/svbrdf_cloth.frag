#version 450 core
// Cloth shaded by the svbrdf method.

#include "svbrdf.glsl"
#include "cloth.glsl"
