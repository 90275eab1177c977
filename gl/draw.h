// Running exported GLSL on a context (gl/context.h): programs of a full-screen triangle and a
// fragment shader, tables uploaded as the textures a user gets (export/texture_file.h), float
// framebuffers read back, and one exported table function evaluated at seeded points, so that
// tests/gl_shader_test.cpp and `ganzfeld bench shaders` compare the GPU with tables::sample the
// same way. Every object is owned (deleted with its owner) and needs a current context.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "export/texture_file.h"
#include "gl/context.h"
#include "models/model.h"
#include "tables/table.h"

namespace ganzfeld::gl {

/// "430 core" or "300 es": what follows `#version`.
const char* glsl_version(Api api);

/// The vertex shader of a full-screen triangle (vertices 0, 1, 2 of glDrawArrays(GL_TRIANGLES, 0, 3)
/// cover the viewport; no vertex buffer).
std::string fullscreen_vertex_shader(Api api);

/// A GL object's name, owned: `Delete` deletes it when the owner goes (0 while empty); moved,
/// never copied.
template <void (*Delete)(GLuint)>
class Owned {
 public:
  Owned() = default;
  explicit Owned(GLuint id) : id_(id) {}
  ~Owned() {
    if (id_ != 0) Delete(id_);
  }
  Owned(Owned&& other) noexcept : id_(other.id_) { other.id_ = 0; }
  Owned& operator=(Owned&& other) noexcept {
    std::swap(id_, other.id_);
    return *this;
  }
  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }

 private:
  GLuint id_ = 0;
};
void delete_program(GLuint id);
void delete_texture(GLuint id);

/// A linked program (0 while empty).
class Program : public Owned<delete_program> {
 public:
  using Owned::Owned;
  /// glGetUniformLocation (-1 when the program has no such active uniform).
  GLint uniform(const char* name) const { return glGetUniformLocation(id(), name); }
};

/// Compiles and links; an empty program and the compiler's or linker's log on failure.
Program link_program(const std::string& vertex, const std::string& fragment, std::string& log);

/// A texture (0 while empty).
using Texture = Owned<delete_texture>;

/// The texture of a table file's texels (export/texture_file.h: read_ktx2 or parse_ktx2) on
/// texture unit `unit`, as docs/shaders.md says to upload it: R32F, R16F, or the 16-bit codes of
/// a unorm16 table as R16; a 3-D texture for g (`volume`), else 2-D; one level, clamped to the
/// edges, GL_LINEAR (hardware filtering) or GL_NEAREST filtering.
Texture upload_texture(const exporting::TextureData& data, bool volume, int unit, bool linear_filter);

/// upload_texture of the KTX2 file a user gets for `table` (ktx2_bytes, parsed back).
Texture upload_table(const tables::Table& table, int unit, bool linear_filter);

/// A framebuffer with one colour renderbuffer of `internal_format` (GL_RGBA32F, GL_RGBA16F, ...),
/// bound, with the viewport set to it.
class Framebuffer {
 public:
  Framebuffer(int width, int height, GLenum internal_format);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;
  bool complete() const { return complete_; }
  /// The pixels as RGBA floats, bottom row first.
  std::vector<float> read_rgba() const;

 private:
  int width_ = 0, height_ = 0;
  GLuint framebuffer_ = 0, color_ = 0;
  bool complete_ = false;
};

/// An empty vertex array, bound (core profiles draw nothing without one).
class VertexArray {
 public:
  VertexArray();
  ~VertexArray();
  VertexArray(const VertexArray&) = delete;
  VertexArray& operator=(const VertexArray&) = delete;

 private:
  GLuint id_ = 0;
};

/// `source` with every texture call outside comments (texture, texelFetch, textureLod, textureGrad,
/// textureGather, textureProj, their Offset forms, ...) wrapped as (gz_fetches += 1, CALL): a
/// shader that declares `int gz_fetches = 0;` before the wrapped code counts the fetches it
/// executes (per pixel: what `bench shaders` reports). Calls inside a call's arguments are
/// wrapped too.
std::string count_texture_fetches(const std::string& source);

/// Lookup points of one law: seeded (i·n, j·n, phi) (tables::validation_points of law g) as
/// vectors in a seeded random frame (n any unit vector; i and j of random lengths, since the
/// exported functions take any frame and need not-unit i and j), and the law's coordinates in the
/// local frame that tables::sample takes.
struct LookupPoints {
  int side = 0;                        ///< side x side points, one pixel each
  std::vector<float> i, j, n;          ///< RGBA per point, the input textures
  std::vector<std::vector<double>> x;  ///< tables::coordinates(law, i, j) in the local frame
};
LookupPoints lookup_points(Law law, int side, std::uint64_t seed);

/// The exported function of `table` (export/glsl.h: glsl_table_snippet) evaluated at every point,
/// one pixel each, with `define` (e.g. "GANZFELD_HARDWARE_FILTER"; "" for none) defined before
/// the snippet and the table's texture filtered linearly or not (upload_table), into an RGBA32F
/// framebuffer; also the texture fetches each lookup executed (count_texture_fetches). Empty and
/// `error` on a compile or link failure.
struct Lookups {
  std::vector<float> values;
  std::vector<int> fetches;
};
Lookups table_function_at_points(const tables::Table& table, const LookupPoints& points, Api api,
                                 const std::string& define, bool linear_filter, std::string& error);

}  // namespace ganzfeld::gl
