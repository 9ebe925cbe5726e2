// A headless OpenGL 4.5 core context through EGL (no window system), owned as an object.
#include "gl/gl_context.hpp"

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "gl/gl_api.hpp"

namespace surftrace::gl {
namespace {

constexpr const char* kInstallHint =
    "install Mesa's EGL and software rasteriser (Debian: libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0) "
    "or, on an NVIDIA machine, the driver's EGL library (libnvidia-egl / libEGL_nvidia.so.0 and its "
    "GLVND vendor file in /usr/share/glvnd/egl_vendor.d)";

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "EGL error 0x" + std::to_string(e);
  }
}

struct Opened {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

// Creates a GL 4.5 core context on an initialised display and makes it current without a
// surface. Appends why it failed to `log` and returns EGL_NO_CONTEXT on failure.
EGLContext createContext(EGLDisplay display, std::string& log) {
  const char* ext = eglQueryString(display, EGL_EXTENSIONS);
  if (!hasExtension(ext, "EGL_KHR_surfaceless_context")) {
    log += " (no EGL_KHR_surfaceless_context)";
    return EGL_NO_CONTEXT;
  }
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    log += " (eglBindAPI(EGL_OPENGL_API): " + eglErrorName(eglGetError()) + ")";
    return EGL_NO_CONTEXT;
  }
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(ext, "EGL_KHR_no_config_context")) {
    // Without configless contexts any config that can render GL will do: nothing is ever
    // drawn to a surface of it, only to our own framebuffer objects.
    const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
    EGLint count = 0;
    if (eglChooseConfig(display, want, &config, 1, &count) != EGL_TRUE || count < 1) {
      log += " (no EGL_KHR_no_config_context and no OpenGL config)";
      return EGL_NO_CONTEXT;
    }
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    log += " (eglCreateContext for OpenGL 4.5 core: " + eglErrorName(eglGetError()) + ")";
    return EGL_NO_CONTEXT;
  }
  if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
    log += " (eglMakeCurrent without a surface: " + eglErrorName(eglGetError()) + ")";
    eglDestroyContext(display, context);
    return EGL_NO_CONTEXT;
  }
  return context;
}

Opened tryDisplay(EGLenum platform, void* native, const std::string& name, std::string& log) {
  Opened o;
  log += "\n  " + name + ":";
  o.display = eglGetPlatformDisplay(platform, native, nullptr);
  if (o.display == EGL_NO_DISPLAY) {
    log += " eglGetPlatformDisplay failed (" + eglErrorName(eglGetError()) + ")";
    return o;
  }
  EGLint major = 0, minor = 0;
  if (eglInitialize(o.display, &major, &minor) != EGL_TRUE) {
    log += " eglInitialize failed (" + eglErrorName(eglGetError()) + ")";
    o.display = EGL_NO_DISPLAY;
    return o;
  }
  log += " EGL " + std::to_string(major) + "." + std::to_string(minor);
  o.context = createContext(o.display, log);
  return o;
}

}  // namespace

GlContext::GlContext() {
  // eglGetPlatformDisplay needs EGL 1.5 client extensions; a NULL answer means the EGL
  // library (or its GLVND vendor) is missing or too old.
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (client == nullptr)
    throw std::runtime_error(std::string("EGL: no client extensions (EGL 1.5 with EGL_EXT_client_extensions needed); ") +
                             kInstallHint);
  std::string log;
  Opened o;
  if (hasExtension(client, "EGL_MESA_platform_surfaceless")) {
    o = tryDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, "surfaceless (EGL_MESA_platform_surfaceless)", log);
    if (o.context != EGL_NO_CONTEXT) platform_ = "surfaceless";
  } else {
    log += "\n  surfaceless: EGL_MESA_platform_surfaceless not offered";
  }
  if (o.context == EGL_NO_CONTEXT) {
    if (hasExtension(client, "EGL_EXT_device_enumeration") && hasExtension(client, "EGL_EXT_platform_device")) {
      auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
      EGLint count = 0;
      if (queryDevices != nullptr && queryDevices(0, nullptr, &count) == EGL_TRUE && count > 0) {
        std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
        queryDevices(count, devices.data(), &count);
        for (EGLint i = 0; i < count && o.context == EGL_NO_CONTEXT; ++i) {
          o = tryDisplay(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<std::size_t>(i)], "device " + std::to_string(i), log);
          if (o.context != EGL_NO_CONTEXT) platform_ = "device";
        }
      } else {
        log += "\n  device platform: no EGL devices";
      }
    } else {
      log += "\n  device platform: EGL_EXT_device_enumeration/EGL_EXT_platform_device not offered";
    }
  }
  if (o.context == EGL_NO_CONTEXT)
    throw std::runtime_error("EGL: could not create a headless OpenGL 4.5 core context; tried:" + log + "\n" +
                             kInstallHint);
  display_ = o.display;
  context_ = o.context;
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  renderer_ = renderer != nullptr ? renderer : "?";
  version_ = version != nullptr ? version : "?";
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 45) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    throw std::runtime_error("OpenGL 4.5 core needed, the driver gave " + version_ + " (" + renderer_ + "); " +
                             kInstallHint);
  }
}

GlContext::~GlContext() {
  // The display is deliberately not terminated: EGL hands every caller the same display
  // for the same platform, so eglTerminate would pull it from under another live
  // GlContext (EGL_KHR_display_reference is not offered by Mesa 22). The driver keeps it.
  // Unbind only our own context: another live GlContext may be the current one.
  if (eglGetCurrentContext() == context_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglReleaseThread();
  } else {
    eglDestroyContext(display_, context_);  // EGL frees it once no thread has it current
  }
}

std::string GlContext::description() const { return renderer_ + " | " + version_ + " | EGL " + platform_; }

void GlContext::makeCurrent() const {
  if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE)
    throw std::runtime_error("EGL: eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")");
}

void checkGlError(const char* what) {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return;
  std::string name;
  switch (e) {
    case GL_INVALID_ENUM: name = "GL_INVALID_ENUM"; break;
    case GL_INVALID_VALUE: name = "GL_INVALID_VALUE"; break;
    case GL_INVALID_OPERATION: name = "GL_INVALID_OPERATION"; break;
    case GL_INVALID_FRAMEBUFFER_OPERATION: name = "GL_INVALID_FRAMEBUFFER_OPERATION"; break;
    case GL_OUT_OF_MEMORY: name = "GL_OUT_OF_MEMORY"; break;
    default: name = "GL error 0x" + std::to_string(e); break;
  }
  while (glGetError() != GL_NO_ERROR) {
  }  // GL may queue several flags; report the first, clear the rest
  throw std::runtime_error(std::string("OpenGL: ") + what + ": " + name);
}

}  // namespace surftrace::gl
