// gl_objects.h — move-only RAII owners of GL object names, and buffer read-back.
// Each owner deletes its object in the destructor; the context must still be
// current then (destroy GL objects before their GlContext).
#pragma once
#include <epoxy/gl.h>

#include <cstddef>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "gpu/gl_check.h"

namespace ft {

// Owner of one GL name; Traits::destroy(GLuint) deletes it.
template <class Traits>
class GlObject {
 public:
  GlObject() = default;
  explicit GlObject(GLuint id) : id_(id) {}
  ~GlObject() { reset(); }
  GlObject(GlObject&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  GlObject& operator=(GlObject&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  // Gives up ownership without deleting.
  GLuint release() { return std::exchange(id_, 0); }
  void reset(GLuint id = 0) {
    if (id_ != 0) Traits::destroy(id_);
    id_ = id;
  }

 private:
  GLuint id_ = 0;
};

namespace detail {
struct ProgramTraits {
  static void destroy(GLuint id) { glDeleteProgram(id); }
};
struct ShaderTraits {
  static void destroy(GLuint id) { glDeleteShader(id); }
};
struct VertexArrayTraits {
  static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
};
struct QueryTraits {
  static void destroy(GLuint id) { glDeleteQueries(1, &id); }
};
struct TextureTraits {
  static void destroy(GLuint id) { glDeleteTextures(1, &id); }
};
struct FramebufferTraits {
  static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct RenderbufferTraits {
  static void destroy(GLuint id) { glDeleteRenderbuffers(1, &id); }
};
struct BufferTraits {
  static void destroy(GLuint id) { glDeleteBuffers(1, &id); }
};
}  // namespace detail

// Program: Program p(buildProgram({...}, defines));
using Program = GlObject<detail::ProgramTraits>;
using Shader = GlObject<detail::ShaderTraits>;
using Texture = GlObject<detail::TextureTraits>;

class Framebuffer : public GlObject<detail::FramebufferTraits> {
 public:
  using GlObject::GlObject;
  static Framebuffer create() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    glCheck("glCreateFramebuffers");
    return Framebuffer(id);
  }
};

class Renderbuffer : public GlObject<detail::RenderbufferTraits> {
 public:
  using GlObject::GlObject;
  static Renderbuffer create() {
    GLuint id = 0;
    glCreateRenderbuffers(1, &id);
    glCheck("glCreateRenderbuffers");
    return Renderbuffer(id);
  }
};

class VertexArray : public GlObject<detail::VertexArrayTraits> {
 public:
  using GlObject::GlObject;
  static VertexArray create() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    glCheck("glCreateVertexArrays");
    return VertexArray(id);
  }
};

class Query : public GlObject<detail::QueryTraits> {
 public:
  using GlObject::GlObject;
  // target: GL_TIME_ELAPSED, GL_PRIMITIVES_GENERATED, GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, ...
  static Query create(GLenum target) {
    GLuint id = 0;
    glCreateQueries(target, 1, &id);
    glCheck("glCreateQueries");
    return Query(id);
  }
};

class Buffer : public GlObject<detail::BufferTraits> {
 public:
  Buffer() = default;
  Buffer(GLuint id, std::size_t size) : GlObject(id), size_(size) {}
  Buffer(Buffer&& o) noexcept : GlObject(std::move(o)), size_(std::exchange(o.size_, 0)) {}
  Buffer& operator=(Buffer&& o) noexcept {
    GlObject::operator=(std::move(o));
    size_ = std::exchange(o.size_, 0);
    return *this;
  }

  // Immutable storage (glNamedBufferStorage). data may be null (contents undefined);
  // flags e.g. GL_DYNAMIC_STORAGE_BIT to allow update(), GL_MAP_READ_BIT, ...
  static Buffer create(std::size_t size, const void* data = nullptr,
                       GLbitfield flags = GL_DYNAMIC_STORAGE_BIT) {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    // Zero-sized storage is an error in GL; keep one byte so empty inputs still bind.
    glNamedBufferStorage(id, static_cast<GLsizeiptr>(size == 0 ? 1 : size), size == 0 ? nullptr : data,
                         flags);
    Buffer b(id, size);
    glCheck("Buffer::create (glNamedBufferStorage)");
    return b;
  }
  // Mutable storage (glNamedBufferData), for buffers that are reallocated.
  static Buffer createMutable(std::size_t size, const void* data = nullptr, GLenum usage = GL_DYNAMIC_DRAW) {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    glNamedBufferData(id, static_cast<GLsizeiptr>(size == 0 ? 1 : size), size == 0 ? nullptr : data, usage);
    Buffer b(id, size);
    glCheck("Buffer::createMutable (glNamedBufferData)");
    return b;
  }
  template <class T>
  static Buffer fromVector(const std::vector<T>& v, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT) {
    return create(v.size() * sizeof(T), v.data(), flags);
  }

  std::size_t size() const { return size_; }
  // glNamedBufferSubData; needs GL_DYNAMIC_STORAGE_BIT for immutable storage.
  void update(const void* data, std::size_t bytes, std::size_t byteOffset = 0) {
    glNamedBufferSubData(id(), static_cast<GLintptr>(byteOffset), static_cast<GLsizeiptr>(bytes), data);
    glCheck("Buffer::update (glNamedBufferSubData)");
  }
  // Fills with zero bytes.
  void clear() {
    glClearNamedBufferData(id(), GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
    glCheck("Buffer::clear (glClearNamedBufferData)");
  }
  void bindBase(GLenum target, GLuint index) const { glBindBufferBase(target, index, id()); }

 private:
  std::size_t size_ = 0;
};

// A program must have a buffer on every storage block it declares, even on the
// blocks the pass being dispatched never touches: one small buffer bound to each
// such slot, alive as long as the returned object.
inline Buffer bindUnusedStorageBlocks(std::initializer_list<GLuint> slots, std::size_t size = 64) {
  Buffer b = Buffer::create(size);
  for (GLuint s : slots) b.bindBase(GL_SHADER_STORAGE_BUFFER, s);
  return b;
}

// Reads `count` elements of T starting `byteOffset` bytes into the buffer. Issues
// glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT) first, so shader writes are visible.
template <class T>
std::vector<T> readBuffer(GLuint buffer, std::size_t count, std::size_t byteOffset = 0) {
  std::vector<T> out(count);
  if (count == 0) return out;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(buffer, static_cast<GLintptr>(byteOffset),
                          static_cast<GLsizeiptr>(count * sizeof(T)), out.data());
  glCheck("readBuffer (glGetNamedBufferSubData)");
  return out;
}

}  // namespace ft
