#version 330 core
// The shadow pass: depth only (the vertex shader places the geometry in the light's view).
void main() {}
