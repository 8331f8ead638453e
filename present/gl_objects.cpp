#include "present/gl_objects.hpp"

#include <fmt/format.h>

#include "runtime/error.hpp"

namespace splatcl::present::gl {
namespace {

// The compiler's or linker's log of a shader or program.
std::string info_log(GLuint object, bool program) {
  char log[4096] = {};
  if (program)
    glGetProgramInfoLog(object, sizeof log, nullptr, log);
  else
    glGetShaderInfoLog(object, sizeof log, nullptr, log);
  return log;
}

GLuint compile(GLenum type, const char* source, const char* name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log(shader, false);
    glDeleteShader(shader);
    throw Error(fmt::format("GL shader '{}' does not compile: {}", name, log));
  }
  return shader;
}

}  // namespace

Texture make_texture(GLenum format, int width, int height, GLenum filter) {
  GLuint texture = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &texture);
  Texture owner(texture);
  glTextureStorage2D(texture, 1, format, width, height);
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return owner;
}

Texture make_buffer_texture(GLenum format, GLuint buffer) {
  GLuint texture = 0;
  glCreateTextures(GL_TEXTURE_BUFFER, 1, &texture);
  Texture owner(texture);
  glTextureBuffer(texture, format, buffer);
  return owner;
}

Framebuffer make_framebuffer(const std::vector<GLuint>& colors, GLuint depth, const char* name) {
  GLuint fbo = 0;
  glCreateFramebuffers(1, &fbo);
  Framebuffer owner(fbo);
  std::vector<GLenum> buffers;
  for (std::size_t i = 0; i < colors.size(); ++i) {
    glNamedFramebufferTexture(fbo, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i), colors[i], 0);
    buffers.push_back(static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i));
  }
  if (depth) glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, depth, 0);
  glNamedFramebufferDrawBuffers(fbo, static_cast<GLsizei>(buffers.size()), buffers.data());
  if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error(fmt::format("GL framebuffer '{}' is incomplete", name));
  return owner;
}

Buffer make_buffer() {
  GLuint buffer = 0;
  glCreateBuffers(1, &buffer);
  return Buffer(buffer);
}

VertexArray make_vertex_array() {
  GLuint vao = 0;
  glCreateVertexArrays(1, &vao);
  return VertexArray(vao);
}

Query make_query() {
  GLuint query = 0;
  glGenQueries(1, &query);
  return Query(query);
}

std::vector<float> read_rgba(GLuint framebuffer, GLenum attachment, int width, int height) {
  std::vector<float> rgba(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glReadBuffer(attachment);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rgba.data());
  return rgba;
}

Program::Program(const std::string& vertex, const std::string& fragment, const char* name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex.c_str(), name);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, fragment.c_str(), name);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  program_ = Object<ProgramKind>(glCreateProgram());
  const GLuint program = program_.get();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) throw Error(fmt::format("GL program '{}' does not link: {}", name, info_log(program, true)));
}

}  // namespace splatcl::present::gl
