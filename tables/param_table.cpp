#include "tables/param_table.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "models/registry.h"
#include "util/error.h"
#include "util/names.h"

namespace ganzfeld::tables {

namespace {
constexpr std::array kGrids{util::EnumName<Grid>{Grid::node, "node"}, util::EnumName<Grid>{Grid::texel, "texel"}};
}  // namespace

const char* to_string(Grid grid) { return util::name_of(kGrids, grid); }
Grid parse_grid(const std::string& text) { return util::parse_name(kGrids, "grid", text); }

double alpha_of(const std::string& name, double x) noexcept { return name == kAxisRoughness ? x * x : x; }

double grid_coordinate(const Axis& axis, Grid grid, int k) noexcept {
  if (grid == Grid::node) return axis.node(k);
  return axis.coordinate((static_cast<double>(k) + 0.5) / axis.count);
}

double grid_position(const Axis& axis, Grid grid, double x) noexcept {
  const double u = axis.index_coordinate(x);
  const double last = axis.count - 1;
  if (grid == Grid::node) return u * last;
  return std::clamp(u * axis.count - 0.5, 0.0, last);
}

double Channel::node_error() const noexcept {
  double largest = 0.0;
  for (float e : error) largest = std::max(largest, static_cast<double>(e));
  return largest;
}

std::size_t ParamTable::entries() const noexcept { return static_cast<std::size_t>(entry_count(axes)); }

std::size_t ParamTable::channel_index(const std::string& name) const {
  std::string list;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    if (channels[c].name == name) return c;
    list += (list.empty() ? "" : ", ") + channels[c].name;
  }
  throw InputError("channel '" + name + "' is not in the table; it has: " + list);
}

namespace {

void check_axes(const std::vector<Axis>& axes) {
  if (axes.size() != 2)
    throw InputError("a parameter table has 2 axes, the metadata lists " + std::to_string(axes.size()));
  if (axes[0].name != kAxisAlpha && axes[0].name != kAxisRoughness)
    throw InputError("axis 0 is '" + axes[0].name + "'; expected alpha or roughness");
  if (axes[1].name != kAxisCosThetaI) throw InputError("axis 1 is '" + axes[1].name + "'; expected cos_theta_i");
  for (const Axis& a : axes) {
    if (!(a.min >= 0.0 && a.min < a.max && a.max <= 1.0))
      throw InputError("axis " + a.name + " spans [" + format_number(a.min) + ", " + format_number(a.max) +
                       "]; expected min < max within [0, 1]");
    if (a.count < 2) throw InputError("axis " + a.name + " has " + std::to_string(a.count) + " samples; at least 2");
    if (a.mapping != Mapping::linear && a.mapping != Mapping::sqrt)
      throw InputError("axis " + a.name + " has mapping " + to_string(a.mapping) + "; allowed: linear, sqrt");
  }
}

}  // namespace

void check_param_table(const ParamTable& table) {
  check_axes(table.axes);
  if (table.channels.empty()) throw InputError("a parameter table needs at least one channel");
  if (table.encoding == Encoding::unorm16)
    throw InputError("encoding unorm16 is for law tables; a parameter table allows: half, float");
  if (!std::isfinite(table.tolerance) || !(table.tolerance > 0.0))
    throw InputError("tolerance " + format_number(table.tolerance) + " is not a positive finite number");
  const std::size_t n = table.entries();
  double max_error = 0.0, lookup_error = 0.0;
  for (const Channel& ch : table.channels) {
    const bool plain =
        !ch.name.empty() && ch.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos;
    if (!plain) throw InputError("channel name '" + ch.name + "' is not allowed; expected [a-z_]+");
    if (table.channel_index(ch.name) != static_cast<std::size_t>(&ch - table.channels.data()))
      throw InputError("channel '" + ch.name + "' appears twice");
    if (ch.value.size() != n || ch.error.size() != n)
      throw InputError("channel " + ch.name + " holds " + std::to_string(ch.value.size()) + " entries; the axes need " +
                       std::to_string(n));
    if (ch.unconverged < 0 || static_cast<std::size_t>(ch.unconverged) > n)
      throw InputError("channel " + ch.name + ": unconverged count " + std::to_string(ch.unconverged) +
                       " is outside [0, " + std::to_string(n) + "]");
    for (std::size_t m = 0; m < n; ++m) {
      if (!std::isfinite(ch.value[m]))
        throw InputError("channel " + ch.name + " entry " + std::to_string(m) + " is " + format_number(ch.value[m]) +
                         "; every value must be finite");
      if (!(ch.error[m] >= 0.0f) || !std::isfinite(ch.error[m]))
        throw InputError("channel " + ch.name + " entry " + std::to_string(m) + " has error " +
                         format_number(ch.error[m]) + "; every error must be finite and >= 0");
      max_error = std::max(max_error, static_cast<double>(ch.error[m]));
    }
    const double channel_max = ch.node_error();
    if (!std::isfinite(ch.lookup_error) || !(ch.lookup_error >= channel_max))
      throw InputError("channel " + ch.name + ": lookup_error " + format_number(ch.lookup_error) +
                       " is not a finite number >= its largest entry error " + format_number(channel_max));
    lookup_error = std::max(lookup_error, ch.lookup_error);
  }
  if (table.node_error != max_error)
    throw InputError("max_error " + format_number(table.node_error) + " disagrees with the error data (max " +
                     format_number(max_error) + ")");
  if (table.lookup_error != lookup_error || table.lookup_checks < 1)
    throw InputError("lookup_error " + format_number(table.lookup_error) + " disagrees with the channels' (max " +
                     format_number(lookup_error) + ") or lookup_checks " + std::to_string(table.lookup_checks) +
                     " is not positive");
}

ParamSample sample_param(const ParamTable& table, std::size_t c, double x_param, double mu) noexcept {
  const Channel& ch = table.channels[c];
  const int n_mu = table.axes[1].count;
  int k[2];
  double w[2];
  const double x[2] = {x_param, mu};
  for (int d = 0; d < 2; ++d) {
    const double s = grid_position(table.axes[d], table.grid, x[d]);
    k[d] = std::min(static_cast<int>(std::floor(s)), table.axes[d].count - 2);
    w[d] = s - k[d];
  }
  ParamSample out;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      const double weight = (a ? w[0] : 1.0 - w[0]) * (b ? w[1] : 1.0 - w[1]);
      const std::size_t m = static_cast<std::size_t>(k[0] + a) * n_mu + static_cast<std::size_t>(k[1] + b);
      out.value += weight * ch.value[m];
      out.error += weight * ch.error[m];
    }
  return out;
}

namespace {

/// The axis coordinates at sample positions s (in sample units; -0.5 and count - 0.5 are the
/// ends of a texel axis) between the samples and at the ends, as param_validation_points says.
std::vector<double> validation_coordinates(const Axis& axis, Grid grid) {
  std::vector<double> positions;
  if (grid == Grid::texel) positions.push_back(-0.5);
  for (int k = 0; k + 1 < axis.count; ++k) positions.push_back(k + 0.5);
  if (grid == Grid::texel) positions.push_back(axis.count - 0.5);
  std::vector<double> out;
  for (double s : positions)
    out.push_back(axis.coordinate(grid == Grid::node ? s / (axis.count - 1) : (s + 0.5) / axis.count));
  return out;
}

}  // namespace

std::vector<std::pair<double, double>> param_validation_points(const ParamTable& table) {
  const Axis& parameter = table.axes.at(0);
  const double min_x = parameter.name == kAxisRoughness ? std::sqrt(kMinValidatedAlpha) : kMinValidatedAlpha;
  // Each axis' coordinates, raised to the validated domain, with its lower end added.
  auto within = [&](const Axis& axis, double lowest) {
    std::vector<double> xs = validation_coordinates(axis, table.grid);
    xs.push_back(lowest);
    for (double& x : xs) x = std::max(x, lowest);
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    return xs;
  };
  std::vector<std::pair<double, double>> points;
  for (double x : within(parameter, min_x))
    for (double mu : within(table.axes.at(1), kMinValidatedMu)) points.push_back({x, mu});
  return points;
}

}  // namespace ganzfeld::tables
