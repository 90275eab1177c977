// A baked table of one law (g, h or a) of one model: axes, values, per-entry error, metadata.
// The file format, the axis mappings and the memory layout are specified in docs/lut-format.md;
// the formulas below are the normative ones and the document quotes them.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "integrate/laws.h"

namespace ganzfeld::tables {

/// Throws InputError unless `law` has tables (g, h, a): "law 'f' has no table; allowed: g, h, a".
void require_tabulated(Law law);
/// parse_law for a flag that names a tabulated law; refusals name `flag` and the text.
Law parse_tabulated_law(const std::string& flag, const std::string& text);

/// The version of docs/lut-format.md this code writes and the only one it reads.
inline constexpr int kFormatVersion = 1;

/// How an axis spends its nodes. u in [0, 1] is the index coordinate (node k at u = k/(count-1)),
/// t = (x - min)/(max - min) the normalized coordinate:
///   linear: t = u                      (uniform)
///   sqrt:   t = u^2,  u = sqrt(t)      (dense at min: grazing angles for h and a)
///   cos:    t = (1 - cos(pi u))/2,  u = acos(1 - 2t)/pi   (Chebyshev–Lobatto: dense at both
///           ends; on [-1, 1] this is exactly uniform in the angle theta = pi (1 - u))
enum class Mapping { linear, sqrt, cos };
const char* to_string(Mapping mapping);
/// Throws InputError naming the value and listing linear, sqrt, cos.
Mapping parse_mapping(const std::string& text);

/// How the stored numbers are rounded: IEEE half or single precision (EXR HALF / FLOAT).
enum class Encoding { half, single };
const char* to_string(Encoding encoding);  ///< "half" or "float"
/// Accepts "half" and "float"; throws InputError otherwise.
Encoding parse_encoding(const std::string& text);

/// One node-centred axis: node 0 is exactly min, node count-1 exactly max.
struct Axis {
  std::string name;
  double min = 0.0;
  double max = 1.0;
  int count = 2;
  Mapping mapping = Mapping::linear;

  /// x for the index coordinate u in [0, 1] (clamped).
  double coordinate(double u) const noexcept;
  /// u in [0, 1] for x (x is clamped to [min, max] first).
  double index_coordinate(double x) const noexcept;
  /// x of node k, exact at both ends.
  double node(int k) const noexcept;
};

/// Axis names of format version 1.
inline constexpr const char* kAxisCosThetaI = "cos_theta_i";  ///< i·n
inline constexpr const char* kAxisCosThetaJ = "cos_theta_j";  ///< j·n
inline constexpr const char* kAxisPhi = "phi";                ///< azimuth of j minus that of i

/// The axes of a law for an isotropic model, with the default mappings, given the node counts
/// (g: 3 counts; h, a: 1). Throws InputError for another law, a wrong number of counts or a
/// count below 2.
///   g: cos_theta_i in [-1, 1] (cos), cos_theta_j in [0, 1] (cos), phi in [0, pi] (linear)
///   h: cos_theta_j in [0, 1] (sqrt)
///   a: cos_theta_i in [0, 1] (sqrt)
std::vector<Axis> default_axes(Law law, std::span<const int> counts);

/// default_axes with the mapping of each axis replaced by `mappings[d]` (empty: keep the
/// defaults). Throws InputError when `mappings` is neither empty nor one per axis.
std::vector<Axis> make_axes(Law law, std::span<const int> counts, std::span<const Mapping> mappings);

/// Parses "M", "MxM" or "MxMxM" (M = linear, sqrt or cos) into one mapping per axis of the law;
/// a single M stands for every axis; "default" gives the empty list (the law's defaults).
/// Throws InputError naming the text and the expected form.
std::vector<Mapping> parse_mappings(const std::string& text, Law law);

struct Table {
  Law law = Law::g;
  std::string model;           ///< canonical spec, Model::spec()
  /// Model::content_digest() of the model baked: the bytes of a measured model's data file, whose
  /// path alone (in `model`) does not say what was baked. "" for analytic models, and for tables
  /// written before the attribute existed.
  std::string model_content;
  std::vector<Axis> axes;      ///< slowest first: entry index = ((k0 * n1) + k1) * n2 + k2
  std::vector<float> value;    ///< exactly the stored numbers (half-encoded values are exact floats)
  std::vector<float> error;    ///< per-entry bound: cubature estimate + storage rounding, rounded up
  double tolerance = 0.0;      ///< absolute tolerance the cubature was asked for
  double max_error = 0.0;      ///< max of `error`
  long long unconverged = 0;   ///< entries whose cubature missed the tolerance
  /// Largest |lookup - cubature| (+ the cubature's own error) measured after baking at the
  /// centres of `interpolation_checks` cells, where multilinear interpolation errs most: the
  /// between-node error that `error` (node values only) does not cover. Measured, not a bound.
  double interpolation_error = 0.0;
  long long interpolation_checks = 0;  ///< 0 for tables made before the measurement existed
  std::string command;         ///< the command line that made the table
  std::string version;         ///< ganzfeld version that made it
  Encoding encoding = Encoding::single;

  std::size_t entries() const noexcept;
};

/// Product of the counts; 0 for no axes.
std::uint64_t entry_count(std::span<const Axis> axes) noexcept;

/// Checks the metadata of a table against format version 1 (the model spec one printable line,
/// the content digest empty or well-formed, axes of the law, counts, finite numbers, data sizes,
/// finite values, non-negative errors, max_error): throws InputError with a one-line
/// description of the first problem.
void check_table(const Table& table);

}  // namespace ganzfeld::tables
