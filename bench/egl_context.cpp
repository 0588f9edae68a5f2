#include "bench/egl_context.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

namespace ssgi {
namespace {

bool contextOpen = false;  // see LlvmpipeContext::Open: one display, so one context at a time

bool HasExtension(const char* extensions, const char* name) {
  if (extensions == nullptr) return false;
  const size_t length = std::strlen(name);
  for (const char* at = std::strstr(extensions, name); at != nullptr; at = std::strstr(at + length, name)) {
    const bool starts = at == extensions || at[-1] == ' ';
    const bool ends = at[length] == ' ' || at[length] == '\0';
    if (starts && ends) return true;
  }
  return false;
}

std::string EglFailure(const char* call) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04X", unsigned(eglGetError()));
  return std::string(call) + " failed (EGL error " + code + ")";
}

}  // namespace

std::unique_ptr<LlvmpipeContext> LlvmpipeContext::Open(int rasterThreads, std::string& error) {
  if (contextOpen) {
    error = "an llvmpipe context is already open (one surfaceless EGL display per process)";
    return nullptr;
  }
  if (!HasExtension(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS), "EGL_MESA_platform_surfaceless")) {
    error = "EGL has no surfaceless platform (EGL_MESA_platform_surfaceless): "
            "Mesa's EGL (libegl-mesa0) is not installed";
    return nullptr;
  }
  // Surfaceless EGL picks a GPU's render node when there is one; these make it Mesa's software
  // driver, and that driver llvmpipe (not softpipe), with the benchmark's thread count.
  setenv("LIBGL_ALWAYS_SOFTWARE", "1", 1);
  setenv("GALLIUM_DRIVER", "llvmpipe", 1);
  setenv("LP_NUM_THREADS", std::to_string(rasterThreads).c_str(), 1);

  EGLDisplay display = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) {
    error = EglFailure("eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA)");
    return nullptr;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    error = EglFailure("eglInitialize (no Mesa DRI driver? libgl1-mesa-dri)");
    return nullptr;
  }
  const char* displayExtensions = eglQueryString(display, EGL_EXTENSIONS);
  for (const char* needed : {"EGL_KHR_no_config_context", "EGL_KHR_surfaceless_context", "EGL_KHR_create_context"}) {
    if (!HasExtension(displayExtensions, needed)) {
      error = std::string("the EGL display lacks ") + needed;
      eglTerminate(display);
      return nullptr;
    }
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    error = EglFailure("eglBindAPI(EGL_OPENGL_API)");
    eglTerminate(display);
    return nullptr;
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,       4, EGL_CONTEXT_MINOR_VERSION, 5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    error = EglFailure("eglCreateContext (OpenGL 4.5 core)");
    eglTerminate(display);
    return nullptr;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    error = EglFailure("eglMakeCurrent");
    eglDestroyContext(display, context);
    eglTerminate(display);
    return nullptr;
  }
  std::unique_ptr<LlvmpipeContext> opened(new LlvmpipeContext(display, context, rasterThreads));
  contextOpen = true;
  const std::string renderer = opened->renderer();
  if (renderer.rfind("llvmpipe", 0) != 0) {
    error = "the software OpenGL is not llvmpipe: " + renderer;
    return nullptr;
  }
  return opened;
}

LlvmpipeContext::~LlvmpipeContext() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  // Terminating the display lets the next Open initialize it again, and so read LP_NUM_THREADS again.
  eglTerminate(display_);
  contextOpen = false;
}

std::string LlvmpipeContext::renderer() const {
  const auto text = [](GLenum name) {
    const auto* value = reinterpret_cast<const char*>(glGetString(name));
    return std::string(value != nullptr ? value : "?");
  };
  return text(GL_RENDERER) + ", " + text(GL_VERSION);
}

}  // namespace ssgi
