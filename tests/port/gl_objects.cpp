#include "tests/port/gl_objects.h"

namespace ssgi::port {
namespace {

std::string_view ShaderSource(std::string_view file) {
  for (const EmbeddedShader& shader : kEmbeddedShaders)
    if (shader.file == file) return shader.source;
  throw std::logic_error("no embedded shader " + std::string(file));
}

template <class GetLog>
std::string InfoLog(GLuint object, GetLog getLog) {
  std::vector<char> log(8192, '\0');
  getLog(object, GLsizei(log.size()), nullptr, log.data());
  return log.data();
}

// A shader of `stage` from the `#version` line, common.glsl, `includes` and `file`.
GLuint CompileShader(GLenum stage, std::string_view file, std::initializer_list<std::string_view> includes) {
  static const std::string version = "#version 450 core\n";
  std::vector<std::string_view> parts = {version, ShaderSource("common.glsl")};
  for (std::string_view include : includes) parts.push_back(ShaderSource(include));
  parts.push_back(ShaderSource(file));
  std::vector<const char*> sources;
  std::vector<GLint> lengths;
  for (std::string_view part : parts) {
    sources.push_back(part.data());
    lengths.push_back(GLint(part.size()));
  }
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, GLsizei(sources.size()), sources.data(), lengths.data());
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = InfoLog(shader, glGetShaderInfoLog);
    glDeleteShader(shader);
    throw GlError(std::string(file) + " does not compile: " + log);
  }
  return shader;
}

}  // namespace

Program::Program(std::string_view file, std::initializer_list<std::string_view> includes) {
  Link({CompileShader(GL_COMPUTE_SHADER, file, includes)}, file);
}

Program::Program(std::string_view vertexFile, std::string_view fragmentFile,
                 std::initializer_list<std::string_view> includes) {
  const GLuint vertex = CompileShader(GL_VERTEX_SHADER, vertexFile, includes);
  GLuint fragment = 0;
  try {
    fragment = CompileShader(GL_FRAGMENT_SHADER, fragmentFile, includes);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  Link({vertex, fragment}, fragmentFile);
}

void Program::Link(std::initializer_list<GLuint> shaders, std::string_view what) {
  id_ = glCreateProgram();
  for (GLuint shader : shaders) glAttachShader(id_, shader);
  glLinkProgram(id_);
  for (GLuint shader : shaders) glDeleteShader(shader);
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = InfoLog(id_, glGetProgramInfoLog);
    glDeleteProgram(id_);
    throw GlError(std::string(what) + " does not link: " + log);
  }
}

}  // namespace ssgi::port
