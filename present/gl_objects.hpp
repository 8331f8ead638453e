#pragma once
// Owners of OpenGL object names (RAII): each deletes its object when it goes, moves but does not
// copy. They need the context that made them current when they are destroyed, as every GL call does.
#include <string>
#include <utility>
#include <vector>

#include "present/gl.hpp"

namespace splatcl::present::gl {

template <class Kind>
class Object {
 public:
  Object() = default;
  explicit Object(GLuint name) : name_(name) {}
  ~Object() { reset(); }
  Object(Object&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
  Object& operator=(Object&& other) noexcept {
    if (this != &other) {
      reset();
      name_ = std::exchange(other.name_, 0);
    }
    return *this;
  }
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;

  GLuint get() const { return name_; }
  explicit operator bool() const { return name_ != 0; }
  void reset() {
    if (name_) Kind::destroy(name_);
    name_ = 0;
  }

 private:
  GLuint name_ = 0;
};

struct TextureKind {
  static void destroy(GLuint name) { glDeleteTextures(1, &name); }
};
struct FramebufferKind {
  static void destroy(GLuint name) { glDeleteFramebuffers(1, &name); }
};
struct BufferKind {
  static void destroy(GLuint name) { glDeleteBuffers(1, &name); }
};
struct VertexArrayKind {
  static void destroy(GLuint name) { glDeleteVertexArrays(1, &name); }
};
struct QueryKind {
  static void destroy(GLuint name) { glDeleteQueries(1, &name); }
};
struct ProgramKind {
  static void destroy(GLuint name) { glDeleteProgram(name); }
};

using Texture = Object<TextureKind>;
using Framebuffer = Object<FramebufferKind>;
using Buffer = Object<BufferKind>;
using VertexArray = Object<VertexArrayKind>;
using Query = Object<QueryKind>;

// A 2D texture of one level with `filter` (GL_NEAREST or GL_LINEAR), clamped to its edges.
Texture make_texture(GLenum format, int width, int height, GLenum filter = GL_NEAREST);
// A framebuffer of `colors` (attachments 0, 1, …, all drawn) and an optional depth texture; Error
// naming `name` when it is incomplete.
Framebuffer make_framebuffer(const std::vector<GLuint>& colors, GLuint depth, const char* name);
Buffer make_buffer();
// A buffer texture (texelFetch on a samplerBuffer) over `buffer`'s whole data store as `format`.
Texture make_buffer_texture(GLenum format, GLuint buffer);
VertexArray make_vertex_array();
Query make_query();

// A linked program of a vertex and a fragment shader; Error with the compiler's log naming `name`.
class Program {
 public:
  Program() = default;
  Program(const std::string& vertex, const std::string& fragment, const char* name);
  GLuint get() const { return program_.get(); }
  void use() const { glUseProgram(program_.get()); }
  // -1 for a uniform the program does not use (glUniform* then does nothing, as GL specifies).
  GLint uniform(const char* name) const { return glGetUniformLocation(program_.get(), name); }

 private:
  Object<ProgramKind> program_;
};

}  // namespace splatcl::present::gl

namespace splatcl::present::gl {

// glReadPixels of a colour attachment as RGBA floats, row 0 = bottom.
std::vector<float> read_rgba(GLuint framebuffer, GLenum attachment, int width, int height);

}  // namespace splatcl::present::gl
