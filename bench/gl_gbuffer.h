// ssgi's rasterization work drawn by OpenGL, for the llvmpipe peer benchmarks (bench/README.md) and
// the test that the peer and ssgi cover the same pixels (tests/bench/llvmpipe_peer_test.cpp).
// Everything here needs a current OpenGL 4.5 core context (bench/egl_context.h) and throws
// std::runtime_error when OpenGL refuses a step (a shader that does not compile, an incomplete
// framebuffer).
//
// Both passes draw with ssgi's conventions (core/camera.h, core/raster/raster.h): the ViewProjection's
// reversed-Z matrix, clip control GL_ZERO_TO_ONE so the depth is z_clip / w as ssgi's depth key,
// cleared to 0 and tested with GL_GREATER (ties keep the earlier triangle, as ssgi's), into a 32-bit
// float depth buffer. OpenGL's window origin is bottom-left; Read* return rows top first, as ssgi's
// planes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/material.h"
#include "core/plane.h"

namespace ssgi {

// Triangles in OpenGL buffers: world-space positions, optionally a normal per position, and three
// indices per triangle, counter-clockwise front faces (core/mesh.h).
class GlMesh {
 public:
  GlMesh(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
         const std::vector<uint32_t>& indices);
  ~GlMesh();
  GlMesh(const GlMesh&) = delete;
  GlMesh& operator=(const GlMesh&) = delete;

  size_t triangleCount() const { return triangleCount_; }
  void Draw() const;  // glDrawElements of every triangle with the bound program and framebuffer

 private:
  unsigned vertexArray_ = 0;
  unsigned buffers_[3] = {};  // positions, normals, indices
  size_t triangleCount_ = 0;
};

// A framebuffer of `colorTargets` GL_R32UI textures and a GL_DEPTH_COMPONENT32F depth texture, with
// the program that draws into it.
class GlPass {
 public:
  ~GlPass();
  GlPass(const GlPass&) = delete;
  GlPass& operator=(const GlPass&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  // Colour target `target`, rows top first.
  Plane<uint32_t> ReadTarget(int target) const;
  // The depth buffer: z_clip / w of the nearest surface (ssgi's depth key), 0 where nothing was drawn.
  Plane<float> ReadDepth() const;

 protected:
  GlPass(int width, int height, int colorTargets, const char* vertexShader, const char* fragmentShader);
  // Clears every target to `clearWords` (one per target) and the depth to 0, binds the program,
  // sets viewProjection, draws `mesh` and waits for the result (glFinish).
  void ClearDrawFinish(const uint32_t* clearWords, const ViewProjection& view, const GlMesh& mesh) const;
  unsigned program() const { return program_; }

 private:
  int width_, height_, colorTargets_;
  unsigned framebuffer_ = 0;
  unsigned textures_[5] = {};  // colour targets, then depth
  unsigned program_ = 0;
};

// ssgi's G-buffer (core/gbuffer.h, docs/pipeline.md §G-buffer) for one material without textures:
// word 0 the material's albedo and metallic (PackAlbedoMetallic, once per draw), and per fragment
// word 1 the interpolated view-space normal in oct24 and roughness, word 2 the view depth as float32
// (+inf in the background), word 3 0 (kShadowLit, as RunGBuffer leaves it). Back faces are culled
// unless the material is two-sided.
class GlGBufferPass : public GlPass {
 public:
  GlGBufferPass(int width, int height);
  // One frame: clear, draw, glFinish.
  void Draw(const GlMesh& mesh, const ViewProjection& view, const Material& material) const;
  GBuffer Read() const;
};

// ssgi's visibility buffer (core/raster/raster.h, RasterOutput::kVisibility): depth and the triangle index
// (gl_PrimitiveID; 0xFFFFFFFF where nothing was drawn), no culling.
class GlVisibilityPass : public GlPass {
 public:
  GlVisibilityPass(int width, int height);
  void Draw(const GlMesh& mesh, const ViewProjection& view) const;  // clear, draw, glFinish
};

}  // namespace ssgi
