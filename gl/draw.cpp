#include "gl/draw.h"

#include <array>
#include <cctype>
#include <random>
#include <utility>

#include "export/glsl.h"
#include "tables/bake.h"
#include "tables/sample.h"

namespace ganzfeld::gl {

const char* glsl_version(Api api) { return api == Api::es30 ? "300 es" : "430 core"; }

std::string fullscreen_vertex_shader(Api api) {
  return std::string("#version ") + glsl_version(api) + R"(
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";
}

void delete_program(GLuint id) { glDeleteProgram(id); }
void delete_texture(GLuint id) { glDeleteTextures(1, &id); }

namespace {
GLuint compile(GLenum stage, const std::string& source, std::string& log) {
  const GLuint shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return shader;
  char buffer[8192] = {};
  glGetShaderInfoLog(shader, sizeof buffer, nullptr, buffer);
  log = buffer;
  glDeleteShader(shader);
  return 0;
}
}  // namespace

Program link_program(const std::string& vertex, const std::string& fragment, std::string& log) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex, log);
  if (vs == 0) return {};
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, log);
  if (fs == 0) {
    glDeleteShader(vs);
    return {};
  }
  Program program(glCreateProgram());
  glAttachShader(program.id(), vs);
  glAttachShader(program.id(), fs);
  glLinkProgram(program.id());
  glDeleteShader(vs);  // flagged; freed with the program
  glDeleteShader(fs);
  GLint linked = 0;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &linked);
  if (linked) return program;
  char buffer[8192] = {};
  glGetProgramInfoLog(program.id(), sizeof buffer, nullptr, buffer);
  log = std::string("the program does not link: ") + buffer;
  return {};
}

Texture upload_texture(const exporting::TextureData& data, bool volume, int unit, bool linear_filter) {
  const bool unorm = data.vk_format == exporting::kVkFormatR16Unorm;
  // unorm16: the codes as GL_R16 (normalized: the shader reads code / 65535), as docs/shaders.md says.
  const GLenum internal = unorm ? GL_R16 : data.vk_format == exporting::kVkFormatR16Sfloat ? GL_R16F : GL_R32F;
  const GLenum type = unorm ? GL_UNSIGNED_SHORT : GL_FLOAT;
  const void* texels =
      unorm ? static_cast<const void*>(data.codes.data()) : static_cast<const void*>(data.texels.data());
  GLuint id = 0;
  glGenTextures(1, &id);
  Texture texture(id);
  glActiveTexture(GL_TEXTURE0 + unit);
  const GLenum target = volume ? GL_TEXTURE_3D : GL_TEXTURE_2D;
  glBindTexture(target, id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (volume)
    glTexImage3D(target, 0, internal, data.size.width, data.size.height, data.size.depth, 0, GL_RED, type, texels);
  else glTexImage2D(target, 0, internal, data.size.width, data.size.height, 0, GL_RED, type, texels);
  // Complete without mipmaps, so texelFetch reads level 0 (export/glsl.h).
  const GLint filter = linear_filter ? GL_LINEAR : GL_NEAREST;
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, filter);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTexParameteri(target, wrap, GL_CLAMP_TO_EDGE);
  return texture;
}

Texture upload_table(const tables::Table& table, int unit, bool linear_filter) {
  return upload_texture(exporting::parse_ktx2(exporting::ktx2_bytes(table), table.model), table.law == Law::g, unit,
                        linear_filter);
}

Framebuffer::Framebuffer(int width, int height, GLenum internal_format) : width_(width), height_(height) {
  glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glGenRenderbuffers(1, &color_);
  glBindRenderbuffer(GL_RENDERBUFFER, color_);
  glRenderbufferStorage(GL_RENDERBUFFER, internal_format, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
  complete_ = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  glViewport(0, 0, width, height);
}

Framebuffer::~Framebuffer() {
  glDeleteRenderbuffers(1, &color_);
  glDeleteFramebuffers(1, &framebuffer_);
}

std::vector<float> Framebuffer::read_rgba() const {
  std::vector<float> pixels(static_cast<std::size_t>(width_) * height_ * 4);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, pixels.data());
  return pixels;
}

VertexArray::VertexArray() {
  glGenVertexArrays(1, &id_);
  glBindVertexArray(id_);
}
VertexArray::~VertexArray() { glDeleteVertexArrays(1, &id_); }

std::string count_texture_fetches(const std::string& source) {
  static const std::array<std::string, 17> kNames{"texture",
                                                  "textureOffset",
                                                  "textureLod",
                                                  "textureLodOffset",
                                                  "textureGrad",
                                                  "textureGradOffset",
                                                  "textureProj",
                                                  "textureProjOffset",
                                                  "textureProjLod",
                                                  "textureProjLodOffset",
                                                  "textureProjGrad",
                                                  "textureProjGradOffset",
                                                  "texelFetch",
                                                  "texelFetchOffset",
                                                  "textureGather",
                                                  "textureGatherOffset",
                                                  "textureGatherOffsets"};
  auto identifier_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  std::string out;
  std::size_t at = 0;
  const std::size_t n = source.size();
  while (at < n) {
    if (source.compare(at, 2, "//") == 0) {  // a line comment: as it is
      const std::size_t end = source.find('\n', at);
      const std::size_t stop = end == std::string::npos ? n : end;
      out.append(source, at, stop - at);
      at = stop;
      continue;
    }
    if (source.compare(at, 2, "/*") == 0) {
      const std::size_t end = source.find("*/", at + 2);
      const std::size_t stop = end == std::string::npos ? n : end + 2;
      out.append(source, at, stop - at);
      at = stop;
      continue;
    }
    if (!identifier_char(source[at]) || (at > 0 && identifier_char(source[at - 1]))) {
      out += source[at++];
      continue;
    }
    std::size_t end = at;
    while (end < n && identifier_char(source[end])) ++end;
    const std::string word = source.substr(at, end - at);
    std::size_t open = end;
    while (open < n && std::isspace(static_cast<unsigned char>(source[open]))) ++open;
    const bool is_call = open < n && source[open] == '(';
    bool known = false;
    for (const std::string& name : kNames) known = known || name == word;
    if (!is_call || !known) {
      out.append(source, at, end - at);
      at = end;
      continue;
    }
    int depth = 0;
    std::size_t close = open;
    for (; close < n; ++close) {
      if (source[close] == '(') ++depth;
      if (source[close] == ')' && --depth == 0) break;
    }
    if (close >= n) {  // unbalanced: leave the rest as it is
      out.append(source, at, n - at);
      break;
    }
    out += "(gz_fetches += 1, " + word + "(" + count_texture_fetches(source.substr(open + 1, close - open - 1)) + "))";
    at = close + 1;
  }
  return out;
}

LookupPoints lookup_points(Law law, int side, std::uint64_t seed) {
  const int count = side * side;
  const std::vector<double> g = tables::validation_points(Law::g, static_cast<std::uint64_t>(count), seed);
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), length(0.5, 2.0);
  LookupPoints out;
  out.side = side;
  for (int p = 0; p < count; ++p) {
    const double ci = g[3 * p], cj = g[3 * p + 1], phi = g[3 * p + 2];
    const double si = std::sqrt(1.0 - ci * ci), sj = std::sqrt(1.0 - cj * cj);
    const Vec3 i{si, 0.0, ci}, j{sj * std::cos(phi), sj * std::sin(phi), cj};
    out.x.push_back(tables::coordinates(law, i, j));
    Vec3 n{unit(random), unit(random), unit(random)};
    n = glm::length(n) > 0.1 ? glm::normalize(n) : Vec3{0.0, 0.0, 1.0};
    const Vec3 a = std::abs(n.x) < 0.9 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 1.0, 0.0};
    const Vec3 t = glm::normalize(a - glm::dot(a, n) * n), b = glm::cross(n, t);
    auto world = [&](const Vec3& v, double scale) {
      const Vec3 w = scale * (v.x * t + v.y * b + v.z * n);
      return std::array<float, 4>{static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z), 0.0f};
    };
    for (auto [to, v] : {std::pair{&out.i, world(i, length(random))}, std::pair{&out.j, world(j, length(random))},
                         std::pair{&out.n, world(Vec3{0.0, 0.0, 1.0}, 1.0)}})
      to->insert(to->end(), v.begin(), v.end());
  }
  return out;
}

namespace {
/// A side x side RGBA32F texture of `texels` on texture unit `unit`, bound to sampler `name`.
Texture point_texture(const std::vector<float>& texels, int side, const Program& program, int unit, const char* name) {
  GLuint id = 0;
  glGenTextures(1, &id);
  Texture texture(id);
  glActiveTexture(GL_TEXTURE0 + unit);
  glBindTexture(GL_TEXTURE_2D, id);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, side, side, 0, GL_RGBA, GL_FLOAT, texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glUniform1i(program.uniform(name), unit);
  return texture;
}
}  // namespace

Lookups table_function_at_points(const tables::Table& table, const LookupPoints& points, Api api,
                                 const std::string& define, bool linear_filter, std::string& error) {
  const std::string function = exporting::glsl_function_name(table.model, table.law);
  const std::string args = table.law == Law::g   ? "(gz_table, i, j, n)"
                           : table.law == Law::h ? "(gz_table, j, n)"
                                                 : "(gz_table, i, n)";
  // The fetch counter is declared before the snippet, whose fetches alone it counts.
  const std::string fragment = std::string("#version ") + glsl_version(api) + "\n" +
                               (define.empty() ? "" : "#define " + define + "\n") + "highp int gz_fetches = 0;\n" +
                               count_texture_fetches(exporting::glsl_table_snippet(table)) + "uniform highp " +
                               exporting::glsl_sampler_type(table.law) + " gz_table;\n" + R"(
uniform highp sampler2D u_i;
uniform highp sampler2D u_j;
uniform highp sampler2D u_n;
out vec4 out_value;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec3 i = texelFetch(u_i, p, 0).xyz, j = texelFetch(u_j, p, 0).xyz, n = texelFetch(u_n, p, 0).xyz;
  float value = )" + function + args +
                               R"(;
  out_value = vec4(value, float(gz_fetches), 0.0, 1.0);
}
)";
  Program program = link_program(fullscreen_vertex_shader(api), fragment, error);
  if (!program) return {};
  glUseProgram(program.id());
  const int side = points.side;
  Texture table_texture = upload_table(table, 0, linear_filter);
  glUniform1i(program.uniform("gz_table"), 0);
  const Texture i = point_texture(points.i, side, program, 1, "u_i"),
                j = point_texture(points.j, side, program, 2, "u_j"),
                n = point_texture(points.n, side, program, 3, "u_n");
  const Framebuffer target(side, side, GL_RGBA32F);
  if (!target.complete()) {
    error = "the RGBA32F framebuffer is not complete";
    return {};
  }
  const VertexArray vertices;
  glDrawArrays(GL_TRIANGLES, 0, 3);
  const std::vector<float> pixels = target.read_rgba();
  if (const GLenum status = glGetError(); status != GL_NO_ERROR) {
    error = "GL error " + std::to_string(status);
    return {};
  }
  Lookups out;
  for (std::size_t p = 0; p < points.x.size(); ++p) {  // row p / side is y: as the inputs
    out.values.push_back(pixels[4 * p]);
    out.fetches.push_back(static_cast<int>(pixels[4 * p + 1]));
  }
  return out;
}

}  // namespace ganzfeld::gl
