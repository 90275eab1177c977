#include "fit/samples.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "models/measured.h"
#include "models/registry.h"
#include "util/error.h"

namespace ganzfeld::fit {

using std::numbers::pi;

namespace {

/// Cell boundaries of nodes x[0..n) on [lo, hi]: the midpoints between neighbours, lo and hi at the ends.
std::vector<double> cell_edges(const std::vector<double>& x, double lo, double hi) {
  std::vector<double> edges{lo};
  for (std::size_t k = 1; k < x.size(); ++k) edges.push_back(0.5 * (x[k - 1] + x[k]));
  edges.push_back(hi);
  return edges;
}

/// ∫ sin θ dθ over each node's cell: the polar measure of a direction.
std::vector<double> polar_measure(const std::vector<double>& theta) {
  const std::vector<double> e = cell_edges(theta, 0.0, pi / 2);
  std::vector<double> m;
  for (std::size_t k = 0; k < theta.size(); ++k) m.push_back(std::cos(e[k]) - std::cos(e[k + 1]));
  return m;
}

/// ∫ 4 cos θ_d sin θ_d dθ_d = 2 (sin² b − sin² a) over each θ_d cell (dω_o = 4 cos θ_d dω_h).
std::vector<double> difference_measure(const std::vector<double>& theta_d) {
  const std::vector<double> e = cell_edges(theta_d, 0.0, pi / 2);
  std::vector<double> m;
  for (std::size_t k = 0; k < theta_d.size(); ++k) {
    const double a = std::sin(e[k]), b = std::sin(e[k + 1]);
    m.push_back(2.0 * (b * b - a * a));
  }
  return m;
}

/// Cell lengths of nodes spaced uniformly over a period (φ_d's [0, π) wraps).
std::vector<double> periodic_measure(std::size_t n, double period) { return std::vector<double>(n, period / n); }

/// Cell lengths on [lo, hi] (tabulated φ ∈ [0°, 180°] does not wrap: its ends are nodes).
std::vector<double> interval_measure(const std::vector<double>& x, double lo, double hi) {
  const std::vector<double> e = cell_edges(x, lo, hi);
  std::vector<double> m;
  for (std::size_t k = 0; k < x.size(); ++k) m.push_back(e[k + 1] - e[k]);
  return m;
}

/// Rotation about n by the golden-ratio azimuth of sample number s.
Vec3 rotate_about_normal(const Vec3& v, std::size_t s) {
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  const double x = static_cast<double>(s) * golden;
  const double phi = 2.0 * pi * (x - std::floor(x));
  const double c = std::cos(phi), sn = std::sin(phi);
  return {c * v.x - sn * v.y, sn * v.x + c * v.y, v.z};
}

class Collector {
 public:
  explicit Collector(double max_theta_deg) : min_cos_(std::cos(max_theta_deg * pi / 180.0)) {}
  /// Adds the pair when both directions are above the horizon and within max_theta and the value is valid.
  void add(const Vec3& i, const Vec3& j, double value, double weight) {
    const std::size_t s = counter_++;
    if (!(i.z >= 0.0 && j.z >= 0.0) || i.z < min_cos_ - 1e-12 || j.z < min_cos_ - 1e-12) return;
    if (!(value >= 0.0) || !(weight > 0.0)) return;
    data.i.push_back(rotate_about_normal(i, s));
    data.j.push_back(rotate_about_normal(j, s));
    data.value.push_back(value);
    data.weight.push_back(weight);
  }
  FitData data;

 private:
  double min_cos_;
  std::size_t counter_ = 0;
};

std::string grid_text(const std::array<int, 3>& g) {
  return std::to_string(g[0]) + "x" + std::to_string(g[1]) + "x" + std::to_string(g[2]);
}

/// The MERL-like nodes of `grid`, as angles and measures per axis.
struct HalfDiffGrid {
  std::vector<double> theta_h, theta_d, phi_d, m_h, m_d, m_p;
};
HalfDiffGrid half_diff_grid(const std::array<int, 3>& grid) {
  HalfDiffGrid g;
  for (int k = 0; k < grid[0]; ++k) {
    const double u = static_cast<double>(k) / grid[0];
    g.theta_h.push_back(u * u * (pi / 2));
  }
  for (int k = 0; k < grid[1]; ++k) g.theta_d.push_back(static_cast<double>(k) / grid[1] * (pi / 2));
  for (int k = 0; k < grid[2]; ++k) g.phi_d.push_back(static_cast<double>(k) / grid[2] * pi);
  g.m_h = polar_measure(g.theta_h);
  g.m_d = difference_measure(g.theta_d);
  g.m_p = periodic_measure(g.phi_d.size(), pi);
  return g;
}

FitData merl_samples(const MerlModel& merl, const SampleOptions& options) {
  const std::array<int, 3> full{merl::kThetaHalf, merl::kThetaDiff, merl::kPhiDiff};
  std::array<int, 3> stride{};
  for (int a = 0; a < 3; ++a) {
    if (full[a] % options.grid[a] != 0)
      throw InputError({Named{"grid", grid_text(options.grid)},
                        " does not divide a MERL file's 90x90x180 nodes; allowed: "
                        "counts dividing 90, 90 and 180, e.g. 90x30x30 or 45x45x45"});
    stride[a] = full[a] / options.grid[a];
  }
  const HalfDiffGrid g = half_diff_grid(options.grid);
  Collector out(options.max_theta_deg);
  for (int h = 0; h < options.grid[0]; ++h)
    for (int d = 0; d < options.grid[1]; ++d)
      for (int p = 0; p < options.grid[2]; ++p) {
        const int kh = h * stride[0], kd = d * stride[1], kp = p * stride[2];
        const auto [i, j] = merl::directions(merl::node_angles(kh, kd, kp));
        out.add(i, j, merl.node(kh, kd, kp), g.m_h[h] * g.m_d[d] * g.m_p[p] * 2.0 * 2.0 * pi);
      }
  out.data.source = "own nodes of the MERL file, every " + std::to_string(stride[0]) + "th/" +
                    std::to_string(stride[1]) + "th/" + std::to_string(stride[2]) + "th along theta_h/theta_d/phi_d (" +
                    grid_text(options.grid) + ")";
  return std::move(out.data);
}

FitData tabulated_samples(const TabulatedModel& tab, const SampleOptions& options) {
  const TabulatedBrdf& t = tab.table();
  const double rad = pi / 180.0;
  auto radians = [&](const std::vector<double>& deg) {
    std::vector<double> r;
    for (double x : deg) r.push_back(x * rad);
    return r;
  };
  const std::vector<double> ti = radians(t.theta_i), tr = radians(t.theta_r), ph = radians(t.phi);
  const std::vector<double> m_i = polar_measure(ti), m_r = polar_measure(tr), m_p = interval_measure(ph, 0.0, pi);
  Collector out(options.max_theta_deg);
  std::size_t index = 0;
  for (std::size_t a = 0; a < ti.size(); ++a)
    for (std::size_t b = 0; b < tr.size(); ++b)
      for (std::size_t c = 0; c < ph.size(); ++c, ++index) {
        const Vec3 i{std::sin(ti[a]), 0.0, std::cos(ti[a])};
        const Vec3 j{std::sin(tr[b]) * std::cos(ph[c]), std::sin(tr[b]) * std::sin(ph[c]), std::cos(tr[b])};
        out.add(i, j, t.values[index], m_i[a] * m_r[b] * m_p[c] * 2.0 * 2.0 * pi);
      }
  out.data.source = "own nodes of the tabulated file (" + std::to_string(ti.size()) + "x" + std::to_string(tr.size()) +
                    "x" + std::to_string(ph.size()) + " theta_i x theta_r x phi)";
  return std::move(out.data);
}

FitData model_samples(const Model& model, const SampleOptions& options) {
  const HalfDiffGrid g = half_diff_grid(options.grid);
  Collector out(options.max_theta_deg);
  for (std::size_t h = 0; h < g.theta_h.size(); ++h)
    for (std::size_t d = 0; d < g.theta_d.size(); ++d)
      for (std::size_t p = 0; p < g.phi_d.size(); ++p) {
        const auto [i0, j0] = merl::directions({g.theta_h[h], g.theta_d[d], g.phi_d[p]});
        // The model is evaluated where the sample will lie: after the rotation about n.
        const std::size_t s = (h * g.theta_d.size() + d) * g.phi_d.size() + p;
        const Vec3 i = rotate_about_normal(i0, s), j = rotate_about_normal(j0, s);
        const double value = i0.z >= 0.0 && j0.z >= 0.0 ? model.f(i, j) : -1.0;
        out.add(i0, j0, value, g.m_h[h] * g.m_d[d] * g.m_p[p] * 2.0 * 2.0 * pi);
      }
  out.data.source =
      "the model at the nodes of a MERL-like " + grid_text(options.grid) + " theta_h x theta_d x phi_d grid";
  return std::move(out.data);
}

}  // namespace

std::array<int, 3> parse_grid(const std::string& text) {
  std::array<int, 3> g{};
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%dx%d%c", &g[0], &g[1], &g[2], &tail) != 3 || g[0] < 2 || g[1] < 2 || g[2] < 2 ||
      g[0] > 1000 || g[1] > 1000 || g[2] > 1000)
    throw InputError({Named{"grid", "'" + text + "'"},
                      " is not a grid; expected NHxNDxNP (theta_h x theta_d x phi_d nodes), each in 2..1000"});
  return g;
}

FitData sample_data(const Model& data, const SampleOptions& options) {
  if (!(options.max_theta_deg > 0.0 && options.max_theta_deg <= 90.0))
    throw InputError(
        {Named{"max_theta", format_number(options.max_theta_deg)}, " is not allowed; allowed: (0, 90] degrees"});
  FitData out;
  if (const auto* merl = dynamic_cast<const MerlModel*>(&data)) out = merl_samples(*merl, options);
  else if (const auto* tab = dynamic_cast<const TabulatedModel*>(&data)) out = tabulated_samples(*tab, options);
  else out = model_samples(data, options);
  if (out.size() == 0)
    throw InputError({"the data '" + data.spec() + "' leave no valid sample within ",
                      Named{"max_theta", format_number(options.max_theta_deg)}, " degrees"});
  return out;
}

}  // namespace ganzfeld::fit
