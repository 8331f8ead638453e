#pragma once
// OpenGL 4.5 core entry points. glvnd's libOpenGL exports them and dispatches to whichever vendor
// (EGL or GLX) owns the current context, so one set of prototypes serves offscreen and windowed use.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
