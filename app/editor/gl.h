// OpenGL 3.3 core entry points. On Linux, libGL (libglvnd) exports every core function, so the
// prototypes from glcorearb.h link directly: no loader is needed for our own calls. (ImGui's
// OpenGL3 backend keeps its own loader for its calls.)
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#define GLFW_INCLUDE_NONE
#include <GL/glcorearb.h>
