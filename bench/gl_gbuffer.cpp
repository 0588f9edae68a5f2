#include "bench/gl_gbuffer.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <GL/glcorearb.h>
#include <glm/gtc/type_ptr.hpp>

#include "core/raster/raster.h"

namespace ssgi {
namespace {

constexpr uint32_t kBackgroundDepthBits = 0x7F800000u;  // +inf, kBackgroundDepth

void ThrowOnGlError(const char* step) {
  if (const GLenum code = glGetError(); code != GL_NO_ERROR) {
    throw std::runtime_error(std::string("OpenGL error ") + std::to_string(code) + " in " + step);
  }
}

// `infoLog` is glGetShaderInfoLog or glGetProgramInfoLog.
[[noreturn]] void ThrowWithInfoLog(const char* failure, void (*infoLog)(GLuint, GLsizei, GLsizei*, GLchar*),
                                   GLuint object) {
  char log[2048] = {};
  infoLog(object, sizeof log, nullptr, log);
  throw std::runtime_error(std::string(failure) + log);
}

GLuint CompileShader(GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint compiled = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
  if (!compiled) ThrowWithInfoLog("GLSL does not compile: ", glGetShaderInfoLog, shader);
  return shader;
}

GLuint LinkProgram(const char* vertexSource, const char* fragmentSource) {
  const GLuint vertex = CompileShader(GL_VERTEX_SHADER, vertexSource);
  const GLuint fragment = CompileShader(GL_FRAGMENT_SHADER, fragmentSource);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint linked = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) ThrowWithInfoLog("GLSL does not link: ", glGetProgramInfoLog, program);
  return program;
}

// Rows of a bottom-up OpenGL read-back turned top first, as ssgi's planes.
template <class T>
Plane<T> ReadRows(int width, int height, GLenum format, GLenum type) {
  std::vector<T> pixels(size_t(width) * size_t(height));
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, format, type, pixels.data());
  ThrowOnGlError("glReadPixels");
  Plane<T> plane = MakePlane<T>(size_t(width), size_t(height), T(0));
  for (int y = 0; y < height; ++y) {
    const T* source = pixels.data() + size_t(height - 1 - y) * size_t(width);
    std::copy(source, source + width, plane.MutableRow(size_t(y)));
  }
  return plane;
}

constexpr const char* kGBufferVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 viewProjection;
uniform mat4 view;
out vec3 viewNormal;
out float viewDepth;
void main() {
  gl_Position = viewProjection * vec4(position, 1.0);
  viewNormal = mat3(view) * normal;
  viewDepth = -(view * vec4(position, 1.0)).z;
}
)";

// The packing of core/gbuffer.cpp (docs/pipeline.md §G-buffer), per fragment. Word 0 comes packed
// per material, as ssgi's resolve takes it (GBufferResolveContext::constantWord0) for a material
// without textures.
constexpr const char* kGBufferFragmentShader = R"(#version 450 core
in vec3 viewNormal;
in float viewDepth;
uniform uint materialWord0;
uniform float roughness;
layout(location = 0) out uint word0;
layout(location = 1) out uint word1;
layout(location = 2) out uint word2;
layout(location = 3) out uint word3;
uint Unorm(float x, float scale) { return uint(clamp(x, 0.0, 1.0) * scale + 0.5); }
uint Oct24(vec3 n) {
  vec2 uv = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
  if (n.z < 0.0) {
    vec2 signs = vec2(uv.x >= 0.0 ? 1.0 : -1.0, uv.y >= 0.0 ? 1.0 : -1.0);
    uv = (1.0 - abs(uv.yx)) * signs;
  }
  return Unorm(uv.x * 0.5 + 0.5, 4095.0) | (Unorm(uv.y * 0.5 + 0.5, 4095.0) << 12);
}
void main() {
  word0 = materialWord0;
  word1 = Oct24(normalize(gl_FrontFacing ? viewNormal : -viewNormal)) | (Unorm(roughness, 255.0) << 24);
  word2 = floatBitsToUint(viewDepth);
  word3 = 0u;
}
)";

constexpr const char* kVisibilityVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
uniform mat4 viewProjection;
void main() { gl_Position = viewProjection * vec4(position, 1.0); }
)";

constexpr const char* kVisibilityFragmentShader = R"(#version 450 core
layout(location = 0) out uint triangle;
void main() { triangle = uint(gl_PrimitiveID); }
)";

}  // namespace

GlMesh::GlMesh(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
               const std::vector<uint32_t>& indices)
    : triangleCount_(indices.size() / 3) {
  glCreateVertexArrays(1, &vertexArray_);
  glCreateBuffers(3, buffers_);
  const auto attribute = [&](GLuint location, GLuint buffer, const std::vector<glm::vec3>& values) {
    glNamedBufferStorage(buffer, GLsizeiptr(values.size() * sizeof(glm::vec3)), values.data(), 0);
    glVertexArrayVertexBuffer(vertexArray_, location, buffer, 0, sizeof(glm::vec3));
    glVertexArrayAttribFormat(vertexArray_, location, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vertexArray_, location, location);
    glEnableVertexArrayAttrib(vertexArray_, location);
  };
  attribute(0, buffers_[0], positions);
  if (!normals.empty()) attribute(1, buffers_[1], normals);
  glNamedBufferStorage(buffers_[2], GLsizeiptr(indices.size() * sizeof(uint32_t)), indices.data(), 0);
  glVertexArrayElementBuffer(vertexArray_, buffers_[2]);
  ThrowOnGlError("the mesh upload");
}

GlMesh::~GlMesh() {
  glDeleteVertexArrays(1, &vertexArray_);
  glDeleteBuffers(3, buffers_);
}

void GlMesh::Draw() const {
  glBindVertexArray(vertexArray_);
  glDrawElements(GL_TRIANGLES, GLsizei(triangleCount_ * 3), GL_UNSIGNED_INT, nullptr);
}

GlPass::GlPass(int width, int height, int colorTargets, const char* vertexShader, const char* fragmentShader)
    : width_(width), height_(height), colorTargets_(colorTargets) {
  if (colorTargets < 1 || colorTargets > 4) throw std::runtime_error("GlPass: 1 to 4 colour targets");
  program_ = LinkProgram(vertexShader, fragmentShader);
  glCreateFramebuffers(1, &framebuffer_);
  glCreateTextures(GL_TEXTURE_2D, colorTargets + 1, textures_);
  GLenum drawBuffers[4];
  for (int i = 0; i < colorTargets; ++i) {
    glTextureStorage2D(textures_[i], 1, GL_R32UI, width, height);
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0 + GLenum(i), textures_[i], 0);
    drawBuffers[i] = GL_COLOR_ATTACHMENT0 + GLenum(i);
  }
  glTextureStorage2D(textures_[colorTargets], 1, GL_DEPTH_COMPONENT32F, width, height);
  glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, textures_[colorTargets], 0);
  glNamedFramebufferDrawBuffers(framebuffer_, colorTargets, drawBuffers);
  if (glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("the R32UI + DEPTH_COMPONENT32F framebuffer is incomplete");
  }
  ThrowOnGlError("the framebuffer set-up");
}

GlPass::~GlPass() {
  glDeleteProgram(program_);
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteTextures(colorTargets_ + 1, textures_);
}

void GlPass::ClearDrawFinish(const uint32_t* clearWords, const ViewProjection& view, const GlMesh& mesh) const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, width_, height_);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  for (int i = 0; i < colorTargets_; ++i) glClearBufferuiv(GL_COLOR, i, &clearWords[i]);
  const GLfloat clearDepth = 0.0f;
  glClearBufferfv(GL_DEPTH, 0, &clearDepth);
  glUseProgram(program_);
  glUniformMatrix4fv(glGetUniformLocation(program_, "viewProjection"), 1, GL_FALSE,
                     glm::value_ptr(view.viewProjection));
  mesh.Draw();
  glFinish();
}

Plane<uint32_t> GlPass::ReadTarget(int target) const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glReadBuffer(GL_COLOR_ATTACHMENT0 + GLenum(target));
  return ReadRows<uint32_t>(width_, height_, GL_RED_INTEGER, GL_UNSIGNED_INT);
}

Plane<float> GlPass::ReadDepth() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  return ReadRows<float>(width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT);
}

GlGBufferPass::GlGBufferPass(int width, int height)
    : GlPass(width, height, 4, kGBufferVertexShader, kGBufferFragmentShader) {}

void GlGBufferPass::Draw(const GlMesh& mesh, const ViewProjection& view, const Material& material) const {
  glUseProgram(program());
  glUniformMatrix4fv(glGetUniformLocation(program(), "view"), 1, GL_FALSE, glm::value_ptr(view.view));
  glUniform1ui(glGetUniformLocation(program(), "materialWord0"),
               PackAlbedoMetallic(material.baseColor, material.metallic));
  glUniform1f(glGetUniformLocation(program(), "roughness"), material.roughness);
  if (material.twoSided) {
    glDisable(GL_CULL_FACE);
  } else {
    glEnable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
  }
  const uint32_t clearWords[4] = {0u, 0u, kBackgroundDepthBits, kShadowLit};
  ClearDrawFinish(clearWords, view, mesh);
}

GBuffer GlGBufferPass::Read() const {
  GBuffer gbuffer;
  gbuffer.normalEncoding = NormalEncoding::kOct24;
  for (int word = 0; word < 4; ++word) gbuffer.word[word] = ReadTarget(word);
  return gbuffer;
}

GlVisibilityPass::GlVisibilityPass(int width, int height)
    : GlPass(width, height, 1, kVisibilityVertexShader, kVisibilityFragmentShader) {}

void GlVisibilityPass::Draw(const GlMesh& mesh, const ViewProjection& view) const {
  glDisable(GL_CULL_FACE);
  const uint32_t clearWord = kNoTriangle;
  ClearDrawFinish(&clearWord, view, mesh);
}

}  // namespace ssgi
