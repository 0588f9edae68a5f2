// What the port's runner (tests/port/gl_port.cpp) and its pass drivers share: GL buffer objects of
// 4-byte words, programs made of the embedded shaders (tests/port/embed_shaders.cmake), and the
// error a GL failure throws. Every pass's sources are common.glsl, then the files it includes, then
// its own.
#pragma once

#include <GL/glcorearb.h>

#include <algorithm>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "tests/port/port_shaders.h"

namespace ssgi::port {

constexpr int kGroupSize = 8;  // every compute shader's local_size_x and local_size_y

class GlError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A GL buffer object of 4-byte words; deleted with the object.
class Buffer {
 public:
  explicit Buffer(size_t words, const void* data = nullptr) : words_(words) {
    glCreateBuffers(1, &id_);
    // At least one word: a zero-size store is an error in GL.
    glNamedBufferData(id_, GLsizeiptr(std::max<size_t>(words, 1) * 4), data, GL_DYNAMIC_COPY);
  }
  ~Buffer() { glDeleteBuffers(1, &id_); }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  Buffer(Buffer&& other) noexcept : id_(other.id_), words_(other.words_) { other.id_ = 0; }
  Buffer& operator=(Buffer&& other) noexcept {
    std::swap(id_, other.id_);
    std::swap(words_, other.words_);
    return *this;
  }

  GLuint id() const { return id_; }
  size_t words() const { return words_; }
  std::vector<uint32_t> Download() const {
    std::vector<uint32_t> words(words_);
    glGetNamedBufferSubData(id_, 0, GLsizeiptr(words_ * 4), words.data());
    return words;
  }
  void Bind(GLuint binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_); }

 private:
  GLuint id_ = 0;
  size_t words_ = 0;
};

// A compute program of `file` after common.glsl and `includes`, or a graphics program of a vertex
// and a fragment shader, each after common.glsl and `includes`; deleted with the object.
class Program {
 public:
  explicit Program(std::string_view file, std::initializer_list<std::string_view> includes = {});
  Program(std::string_view vertexFile, std::string_view fragmentFile, std::initializer_list<std::string_view> includes);
  ~Program() { glDeleteProgram(id_); }
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  GLuint id() const { return id_; }

  // Uniforms by name; one the compiler removed as unused is ignored (location -1), as GL does.
  void Set(const char* name, int v) const { glProgramUniform1i(id_, Location(name), v); }
  void Set(const char* name, float v) const { glProgramUniform1f(id_, Location(name), v); }
  void Set(const char* name, int x, int y) const { glProgramUniform2i(id_, Location(name), x, y); }
  void Set(const char* name, float x, float y) const { glProgramUniform2f(id_, Location(name), x, y); }
  void Set(const char* name, float x, float y, float z) const { glProgramUniform3f(id_, Location(name), x, y, z); }
  void Set(const char* name, int x, int y, int z) const { glProgramUniform3i(id_, Location(name), x, y, z); }
  void SetMatrix(const char* name, const float* columns) const {
    glProgramUniformMatrix4fv(id_, Location(name), 1, GL_FALSE, columns);
  }
  void SetArray3(const char* name, const std::vector<float>& xyz) const {
    glProgramUniform3fv(id_, Location(name), GLsizei(xyz.size() / 3), xyz.data());
  }
  void SetArray(const char* name, const std::vector<float>& v) const {
    glProgramUniform1fv(id_, Location(name), GLsizei(v.size()), v.data());
  }
  void SetArray(const char* name, const std::vector<int>& v) const {
    glProgramUniform1iv(id_, Location(name), GLsizei(v.size()), v.data());
  }
  void SetArray2(const char* name, const std::vector<int>& xy) const {
    glProgramUniform2iv(id_, Location(name), GLsizei(xy.size() / 2), xy.data());
  }

  // One invocation per (x, y, z) of width x height x depth; the writes are visible to the next
  // dispatch and to downloads when it returns.
  void Dispatch(int width, int height, int depth = 1) const {
    glUseProgram(id_);
    glDispatchCompute(GLuint((width + kGroupSize - 1) / kGroupSize), GLuint((height + kGroupSize - 1) / kGroupSize),
                      GLuint(depth));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);
  }

 private:
  GLint Location(const char* name) const { return glGetUniformLocation(id_, name); }
  void Link(std::initializer_list<GLuint> shaders, std::string_view what);
  GLuint id_ = 0;
};

}  // namespace ssgi::port
