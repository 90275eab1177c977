// Tables over a model parameter (format version 3, docs/lut-format.md "Version 3: parameter
// axes and channels"): what a real-time shader reads for every roughness of a material at once.
// Two axes, slowest first (parameter, cos_theta_i), and one or more channels, each a value and
// its per-texel error bound. The presets that fill them (DFG, Kulla–Conty) are tables/preset.h.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "tables/table.h"

namespace ganzfeld::tables {

inline constexpr int kParamFormatVersion = 3;

/// Where an axis' samples sit. node: sample k at index coordinate u = k/(count - 1) (ends
/// exact, as version 1 and 2 axes); texel: sample k at u = (k + 0.5)/count, the centre of texel
/// k, which is what a GPU texture lookup with normalized coordinate u returns there (Filament's
/// DFG: NoV = (x + 0.5)/width).
enum class Grid { node, texel };
const char* to_string(Grid grid);  ///< "node" or "texel"
/// Accepts "node" and "texel"; throws InputError naming the text otherwise.
Grid parse_grid(const std::string& text);

/// The parameter axis' names: GGX alpha, or perceptual roughness R with alpha = R².
inline constexpr const char* kAxisAlpha = "alpha";
inline constexpr const char* kAxisRoughness = "roughness";
/// alpha for coordinate x of a parameter axis named `name` (alpha: x; roughness: x²).
double alpha_of(const std::string& name, double x) noexcept;

/// The coordinate of sample k of an axis on a grid (node: Axis::node(k)).
double grid_coordinate(const Axis& axis, Grid grid, int k) noexcept;
/// The sample position s in [0, count - 1] of coordinate x (x clamped to the axis first):
/// node: u (count - 1); texel: u count - 0.5, clamped (a GPU's clamp-to-edge).
double grid_position(const Axis& axis, Grid grid, double x) noexcept;

struct Channel {
  std::string name;          ///< e.g. "dfg_fc"; its error channel in the file is name + "_error"
  std::string definition;    ///< the integral it holds, one line (docs/lut-format.md)
  std::vector<float> value;  ///< entry index = k_param * n_mu + k_mu
  std::vector<float> error;  ///< per-entry bound: cubature estimate + storage rounding, rounded up
  long long unconverged = 0;
  /// THE error of the channel: a bound of |sample_param - the integral| over the table's domain
  /// (parameter alpha >= kMinValidatedAlpha), validated after baking at the points between the
  /// samples and on the domain's edges (param_validation_points) against direct cubature:
  /// kLookupMargin x the largest |lookup - cubature| + cubature error there, and never below the
  /// largest entry of `error`.
  double lookup_error = 0.0;

  double node_error() const noexcept;  ///< the largest entry of `error`
};

struct ParamTable {
  std::string preset;      ///< "dfg" or "kulla-conty"
  std::string layout;      ///< dfg: "filament" or "ue4"; kulla-conty: "kulla-conty"
  std::string model;       ///< the model family, canonical spec with the axis' parameter removed
  std::vector<Axis> axes;  ///< {parameter (alpha or roughness), cos_theta_i}, slowest first
  Grid grid = Grid::texel;
  std::vector<Channel> channels;
  double tolerance = 0.0;       ///< the cubature's absolute tolerance per integral
  double node_error = 0.0;      ///< max over every channel's per-texel error
  double lookup_error = 0.0;    ///< max over every channel's lookup_error: the table's headline
  long long lookup_checks = 0;  ///< validation points behind lookup_error (per channel)
  std::string command, version;
  Encoding encoding = Encoding::single;

  std::size_t entries() const noexcept;  ///< per channel
  /// The channel named `name`; throws InputError listing the table's channels.
  std::size_t channel_index(const std::string& name) const;
};

/// Checks a parameter table (axes, grid, channel names and sizes, finite values, non-negative
/// errors, node_error): throws InputError with a one-line description of the first problem.
void check_param_table(const ParamTable& table);

/// Bilinear lookup of channel c at (parameter x_param, cos_theta_i mu) in the table's grid
/// convention (clamped at the ends); error: the same blend of the per-entry error bounds.
struct ParamSample {
  double value = 0.0;
  double error = 0.0;
};
ParamSample sample_param(const ParamTable& table, std::size_t c, double x_param, double mu) noexcept;

/// The domain over which a parameter table's lookup error is validated: alpha >= kMinValidatedAlpha
/// (below it the charlie sheen has no limit) and cos_theta_i >= kMinValidatedMu (as for every
/// table's lookup error). Towards mu = 0 the albedos of small alpha fall to 0 in a layer about
/// alpha wide that no bilinear table of a few dozen samples resolves (docs/lut-format.md,
/// "Version 3").
inline constexpr double kMinValidatedAlpha = 1e-3;
inline constexpr double kMinValidatedMu = 0.02;

/// The points (parameter coordinate, cos_theta_i) at which a table's lookup is validated: on each
/// axis, the midpoints between consecutive samples, on the texel grid both ends of the axis
/// (where the lookup clamps to the edge texel), and the lower end of the validated domain;
/// every pair of them, each coordinate raised into the validated domain.
std::vector<std::pair<double, double>> param_validation_points(const ParamTable& table);

/// Writes the table as an OpenEXR file of format version 3 (docs/lut-format.md), atomically;
/// check_param_table first, so nothing read_param_table refuses is ever written.
void write_param_table(const ParamTable& table, const std::string& path);
/// The table's axes as the JSON array the file's `ganzfeld.axes` attribute and `info --json` hold:
/// [{name, min, max, count, mapping, grid}, ...], slowest first (docs/lut-format.md).
nlohmann::ordered_json param_axes_json(const ParamTable& table);
/// Reads a version 3 table; refuses (InputError "table 'PATH': ...", one line) anything else.
ParamTable read_param_table(const std::string& path);
/// The ganzfeld.format_version of a file that is an OpenEXR file with that attribute (and sizes
/// that fit, tables/exr_guard.h), else 0: lets info and sample open versions 1 to 3.
int format_version_of(const std::string& path);

}  // namespace ganzfeld::tables
