#version 450 core
// Cloth shaded by the neural method.

#include "neural.glsl"
#include "cloth.glsl"
