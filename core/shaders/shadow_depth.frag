#version 450 core
// Depth only: the rasteriser writes gl_FragDepth.

void main() {}
