// The OpenGL 4.5 core entry points: GLVND's libOpenGL exports them all, so no loader is used.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
