// An OpenGL 4.5 core context on Mesa's llvmpipe, the CPU OpenGL a user would otherwise run a
// deferred pipeline on (docs/design.md §13): the peer of the benchmarks, and the context a GLSL port of
// the passes can run in. No window system and no GPU: EGL's surfaceless platform
// (EGL_MESA_platform_surfaceless) with a context that has no config and no surface
// (EGL_KHR_no_config_context, EGL_KHR_surfaceless_context), so every image is a framebuffer object.
#pragma once

#include <memory>
#include <string>

namespace ssgi {

class LlvmpipeContext {
 public:
  // The context, current on the calling thread, with llvmpipe rasterizing on `rasterThreads` threads
  // (LP_NUM_THREADS; 0 rasterizes on the calling thread). Null, with `error` saying why, where no
  // EGL display or no llvmpipe can be had. It sets LIBGL_ALWAYS_SOFTWARE, GALLIUM_DRIVER and
  // LP_NUM_THREADS in this process's environment, since Mesa reads them only there, when the display
  // is initialized. EGL hands every caller the same surfaceless display, so at most one context lives
  // at a time: a second Open while one lives fails.
  static std::unique_ptr<LlvmpipeContext> Open(int rasterThreads, std::string& error);
  ~LlvmpipeContext();
  LlvmpipeContext(const LlvmpipeContext&) = delete;
  LlvmpipeContext& operator=(const LlvmpipeContext&) = delete;

  int rasterThreads() const { return rasterThreads_; }
  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6".
  std::string renderer() const;

 private:
  LlvmpipeContext(void* display, void* context, int rasterThreads)
      : display_(display), context_(context), rasterThreads_(rasterThreads) {}
  void* display_;  // EGLDisplay and EGLContext, kept opaque so that no user includes EGL
  void* context_;
  int rasterThreads_;
};

}  // namespace ssgi
