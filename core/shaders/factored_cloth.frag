#version 450 core
// Cloth shaded by the factored method.

#include "factored.glsl"
#include "cloth.glsl"
