// A headless OpenGL 4.5 core context through EGL (no window system), owned as an object.
#pragma once

#include <string>

namespace surftrace::gl {

// Opens an EGL display without a window system and makes a GL 4.5 core context current on
// the calling thread with no surface (EGL_KHR_surfaceless_context) and no config
// (EGL_KHR_no_config_context). Platforms tried in order: Mesa's surfaceless platform (llvmpipe
// on a machine without a GPU, or a Mesa GPU driver), then every device of the EGL device
// platform (NVIDIA's driver). The context belongs to the thread that made it: create and use
// it on one thread. Throws std::runtime_error naming what failed and what to install.
class GlContext {
 public:
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)", "4.5 (Core Profile) Mesa 22.3.6".
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }
  // "<renderer> | <version> | EGL <platform>": what goes into every output's metadata.
  std::string description() const;
  // "surfaceless" or "device".
  const std::string& platform() const { return platform_; }

  // Makes this context current on the calling thread again (after another was).
  void makeCurrent() const;

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string renderer_, version_, platform_;
};

// Throws std::runtime_error("<what>: <GL error name>") if glGetError reports an error.
void checkGlError(const char* what);

}  // namespace surftrace::gl
