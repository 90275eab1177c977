// GLSL export: tables/'s mappings and interpolation emitted as GLSL, so a shader samples exactly
// what the CPU samples. The emitted code compiles as GLSL 4.30 core and GLSL ES 3.00; it is a
// snippet without #version, to be included in the user's shader (docs/shaders.md).
//
// What the shader reproduces, step for step, is tables/sample.h:
//   coordinates  g: (i·n, j·n, relative azimuth in [0, pi]) (tables::coordinates), for a
//                lobe-frame table then (theta_j, psi, beta) (tables::lobe_coordinates);  h: j·n;  a: i·n
//   index u      per axis: the mapping inverted, clamped to [0, 1]          (Axis::index_coordinate)
//   cell         s = u (count - 1), k = min(floor s, count - 2), t = s - k
//   value        linear: multilinear blend of the 2^d nodes; catmull-rom: the 4^d nodes with the
//                weights of tables::axis_taps (the same end rules), fetched with texelFetch
// so the GPU result differs from tables::sample only by float arithmetic (tests/gl_shader_test.cpp
// compares them point by point). Hardware filtering (define GANZFELD_HARDWARE_FILTER) samples at
// the texel centre rule (u (count-1) + 0.5)/count instead: one fetch for linear, 3 per axis for
// Catmull–Rom (the two middle nodes in one linear fetch); faster, but GPUs blend with
// low-precision weights (docs/shaders.md).
//
// Texture layout: a table of axes (slowest first) n0 [x n1 x n2] is a 3-D texture of width n2,
// height n1, depth n0 (texel (k2, k1, k0) = node (k0, k1, k2)), or for 1-D laws a 2-D texture of
// width n0 and height 1 (GLSL ES has no 1-D textures). One channel: R32F (float tables) or R16F
// (half tables; the stored values are exactly representable either way), or R16 (unorm16 tables:
// the codes, normalized to u / 65535 by the GPU; the function returns offset + scale x lookup).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "models/model.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "tables/table.h"

namespace ganzfeld::exporting {

/// "gz_" + the text with every run of characters outside [A-Za-z0-9] replaced by one '_'
/// (GLSL reserves identifiers containing "__" and the prefix "gl_").
std::string glsl_identifier(const std::string& text);

/// Name of the GLSL function that samples `table`: gz_<spec>_<law>, e.g. gz_specular_alpha_8_g.
std::string glsl_function_name(const std::string& spec, Law law);

/// The sampler type of a table's texture: "sampler3D" for g, "sampler2D" for h and a.
const char* glsl_sampler_type(Law law);

/// Shared helpers (index mappings, coordinates, the lobe frame, linear and Catmull–Rom fetches) once, inside an include
/// guard so that several exported snippets can be pasted into one shader.
std::string glsl_common();

/// A comment block with the table's metadata, error, axes and texture layout, then the function
///   g: float NAME(highp sampler3D table, vec3 i, vec3 j, vec3 n)
///   h: float NAME(highp sampler2D table, vec3 j, vec3 n)
///   a: float NAME(highp sampler2D table, vec3 i, vec3 n)
/// (n unit; i and j need not be unit). Checks the table first (check_table).
std::string glsl_table_function(const tables::Table& table);

/// One line naming the lookup glsl_table_function(table) performs, from the table's metadata:
/// frame (and peak), interpolation, nodes per axis, encoding and the filter its bound covers with
/// its fetches, e.g. "warped frame (mirror peak), linear, 25x49x17 nodes, float, hardware (1 fetch)"
/// (`ganzfeld bench shaders` and `bench render` label their tables with it).
std::string lookup_scheme(const tables::Table& table);

/// glsl_common() + glsl_table_function(table): one self-contained snippet per table file.
std::string glsl_table_snippet(const tables::Table& table);

/// Throws InputError unless `table` is law `law` of `model` (tables::same_model: the spec apart
/// from file paths, and the same data): the check the exporter makes before it binds a table
/// file to a shader function.
void check_table_is(const tables::Table& table, const Model& model, Law law);

/// Throws what glsl_scene_shader would throw about the scene itself (a lobe lit by a collimated
/// light without a GLSL f; under extended lights an anisotropic lobe, or one with a mirror delta
/// that render adds and no table holds: Model::mirror_reflectance), so that the exporter can
/// refuse before it bakes any table.
void check_scene_exportable(const Scene& scene);

/// The sampler uniform of a scene table: "gz_tex_<spec>_<law>".
std::string glsl_sampler_name(const std::string& spec, Law law);

/// The reference shading snippet of a scene (the rasterizer's shade(), rasterizer/shading.h):
/// uniforms for the tables, their sampling functions, f of each lobe lit by a collimated light,
/// the lights as constants, one function per material used by an object
///   vec3 gz_material_<k>_<name>(vec3 n, vec3 j)        (world space, unit n and j)
/// and vec3 gz_scene_radiance(int material, vec3 n, vec3 j) with material = index in the scene
/// file, as `plan` (scene/plan.h, made for this scene) says: each table is checked with
/// check_table_is; Lambert lobes use their closed forms; a lobe the plan shades directly is
/// refused. `source` names the scene file in the header comment.
std::string glsl_scene_shader(const Scene& scene, const scene::ShadingPlan& plan, const std::string& source);

}  // namespace ganzfeld::exporting
