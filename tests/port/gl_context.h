// An OpenGL 4.5 core context without a window: EGL's surfaceless platform
// (EGL_MESA_platform_surfaceless), made current on the calling thread, on Mesa's llvmpipe.
#pragma once

#include <memory>
#include <string>

#include <EGL/egl.h>

namespace ssgi::port {

class GlContext {
 public:
  // The context, or nullptr with `error` saying what is missing (no surfaceless EGL, no Mesa
  // driver, no OpenGL 4.5 core): where that happens the port cannot run, which is not its failure.
  static std::unique_ptr<GlContext> Open(std::string& error);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  std::string Renderer() const;  // "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6"

 private:
  GlContext(EGLDisplay display, EGLContext context) : display_(display), context_(context) {}
  EGLDisplay display_;
  EGLContext context_;
};

}  // namespace ssgi::port
