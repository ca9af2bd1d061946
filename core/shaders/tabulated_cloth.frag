#version 450 core
// Cloth shaded by the tabulated method.

#include "tabulated.glsl"
#include "cloth.glsl"
