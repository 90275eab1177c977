#include "bench/genz_bench.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>

#include <cubature.h>
#include <tbb/parallel_for.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

#include "bench/cubature_bench.h"
#include "integrate/cubature.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::bench {

namespace {

using std::numbers::pi;

/// Genz's TESTPACK difficulty: Σ aᵢ = kDifficulty / n^kExponent, per family in enum order.
constexpr std::array<double, 6> kDifficulty{110.0, 600.0, 600.0, 100.0, 150.0, 100.0};
constexpr std::array<double, 6> kExponent{1.5, 2.0, 2.0, 1.0, 2.0, 2.0};

int index_of(GenzFamily family) { return static_cast<int>(family); }

std::string number(double x, int digits = 3) { return significant(x, digits); }

}  // namespace

const char* to_string(GenzFamily family) {
  switch (family) {
    case GenzFamily::oscillatory: return "oscillatory";
    case GenzFamily::product_peak: return "product peak";
    case GenzFamily::corner_peak: return "corner peak";
    case GenzFamily::gaussian: return "Gaussian";
    case GenzFamily::c0: return "C0";
    case GenzFamily::discontinuous: return "discontinuous";
  }
  return "?";
}

double GenzInstance::operator()(const double* x) const {
  double sum = 0.0, product = 1.0;
  switch (family) {
    case GenzFamily::oscillatory:
      sum = 2.0 * pi * u[0];
      for (int d = 0; d < dimension; ++d) sum += a[d] * x[d];
      return std::cos(sum);
    case GenzFamily::product_peak:
      for (int d = 0; d < dimension; ++d) product /= 1.0 / (a[d] * a[d]) + (x[d] - u[d]) * (x[d] - u[d]);
      return product;
    case GenzFamily::corner_peak:
      sum = 1.0;
      for (int d = 0; d < dimension; ++d) sum += a[d] * x[d];
      return std::pow(sum, -(dimension + 1));
    case GenzFamily::gaussian:
      for (int d = 0; d < dimension; ++d) sum += a[d] * a[d] * (x[d] - u[d]) * (x[d] - u[d]);
      return std::exp(-sum);
    case GenzFamily::c0:
      for (int d = 0; d < dimension; ++d) sum += a[d] * std::abs(x[d] - u[d]);
      return std::exp(-sum);
    case GenzFamily::discontinuous:
      for (int d = 0; d < dimension; ++d) {
        if (x[d] > u[d]) return 0.0;
        sum += a[d] * x[d];
      }
      return std::exp(sum);
  }
  return 0.0;
}

double GenzInstance::l1_norm() const {
  // |cos| <= 1 on a box of volume 1; every other family is positive.
  return family == GenzFamily::oscillatory ? 1.0 : static_cast<double>(std::abs(exact));
}

long double genz_exact(const GenzInstance& in) {
  using Long = long double;
  const int n = in.dimension;
  Long value = 1.0L;
  switch (in.family) {
    case GenzFamily::oscillatory: {
      // Re[e^{2πi u₁} Π (e^{i aₖ} − 1) / (i aₖ)], (e^{ia} − 1)/(ia) = sin(a)/a + i (1 − cos a)/a.
      Long re = std::cos(2.0L * std::numbers::pi_v<Long> * in.u[0]),
           im = std::sin(2.0L * std::numbers::pi_v<Long> * in.u[0]);
      for (int d = 0; d < n; ++d) {
        const Long a = in.a[d], c = std::sin(a) / a, s = 2.0L * std::sin(a / 2) * std::sin(a / 2) / a;
        const Long next_re = re * c - im * s, next_im = re * s + im * c;
        re = next_re;
        im = next_im;
      }
      return re;
    }
    case GenzFamily::product_peak:
      for (int d = 0; d < n; ++d)
        value *= Long(in.a[d]) * (std::atan(Long(in.a[d]) * (1 - Long(in.u[d]))) + std::atan(Long(in.a[d]) * in.u[d]));
      return value;
    case GenzFamily::corner_peak: {
      // ∫(1 + a·x)^−(n+1) over [0,1]^n = Σ_{S ⊆ axes} (−1)^|S| / (1 + Σ_S aᵢ) / (n! Π aᵢ).
      Long sum = 0.0L, product = 1.0L;
      for (int subset = 0; subset < (1 << n); ++subset) {
        Long t = 1.0L;
        int bits = 0;
        for (int d = 0; d < n; ++d)
          if (subset >> d & 1) t += in.a[d], ++bits;
        sum += (bits % 2 ? -1.0L : 1.0L) / t;
      }
      for (int d = 0; d < n; ++d) product *= in.a[d];
      return sum / (product * (n == 1 ? 1.0L : 2.0L));
    }
    case GenzFamily::gaussian:
      for (int d = 0; d < n; ++d)
        value *= std::sqrt(std::numbers::pi_v<Long>) / (2 * Long(in.a[d])) *
                 (std::erf(Long(in.a[d]) * (1 - Long(in.u[d]))) + std::erf(Long(in.a[d]) * in.u[d]));
      return value;
    case GenzFamily::c0:
      for (int d = 0; d < n; ++d)
        value *= (-std::expm1(-Long(in.a[d]) * in.u[d]) - std::expm1(-Long(in.a[d]) * (1 - Long(in.u[d])))) / in.a[d];
      return value;
    case GenzFamily::discontinuous:
      for (int d = 0; d < n; ++d) value *= std::expm1(Long(in.a[d]) * in.u[d]) / in.a[d];
      return value;
  }
  return 0.0L;
}

GenzInstance make_genz_instance(GenzFamily family, int dimension, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  GenzInstance in;
  in.family = family;
  in.dimension = dimension;
  double total = 0.0;
  for (int d = 0; d < dimension; ++d) {
    in.a[d] = uniform(rng);
    in.u[d] = uniform(rng);
    total += in.a[d];
  }
  const double scale = kDifficulty[index_of(family)] / std::pow(dimension, kExponent[index_of(family)]) / total;
  for (int d = 0; d < dimension; ++d) in.a[d] *= scale;
  in.exact = genz_exact(in);
  return in;
}

std::vector<SingularLine> singular_lines(const GenzInstance& in) {
  std::vector<SingularLine> lines;
  if (in.family != GenzFamily::c0 && in.family != GenzFamily::discontinuous) return lines;
  for (int d = 0; d < in.dimension; ++d)
    lines.push_back({d, in.u[d], in.family == GenzFamily::discontinuous && in.dimension == 2 ? in.u[1 - d] : 1.0});
  return lines;
}

double min_relative_tolerance() { return kRoundingUlps * std::numeric_limits<double>::epsilon(); }

GenzOptions quick_genz_options() { return {.instances = 3, .tolerances = {1e-4, 1e-10}, .budget = 200'000}; }

void check_genz_options(const GenzOptions& options) {
  if (options.instances < 1)
    throw InputError({Named{"instances", std::to_string(options.instances)}, " is not allowed; expected at least 1"});
  for (double t : options.tolerances)
    if (!(t >= min_relative_tolerance() && t < 1.0))
      throw InputError({Named{"tolerances", number(t)}, " is not allowed; expected relative tolerances in [" +
                                                            number(min_relative_tolerance()) +
                                                            ", 1) (below it no double-precision rule resolves)"});
  if (options.tolerances.empty()) throw InputError("no tolerance given; expected at least one");
  for (int d : options.dimensions) {
    if (d != 1 && d != 2) throw InputError("dimension " + std::to_string(d) + " is not allowed; allowed: 1, 2");
    const long long panel = d == 1 ? kRuleNodes : kRuleNodes * kRuleNodes;
    if (options.budget < panel)
      throw InputError({Named{"budget", std::to_string(options.budget)},
                        " is below one panel of " + std::to_string(panel) + " evaluations in " + std::to_string(d) +
                            "-D; allowed: >= " + std::to_string(panel)});
  }
}

const std::vector<std::string>& genz_competitors() {
  static const std::vector<std::string> names{"ours", "hcubature", "pcubature", "boost_gauss_kronrod",
                                              "boost_tanh_sinh"};
  return names;
}

double GenzCell::geometric_mean_evaluations() const { return runs ? std::exp(log_evaluations / runs) : 0.0; }

namespace {

struct CappedOut {};

/// The one integrand wrapper every competitor goes through: counts evaluations, enforces the cap
/// (by exception for the Boost integrators; libcubature gets it as maxEval) and notes on which
/// sides of each singular line a point was evaluated.
class Counted {
 public:
  Counted(const GenzInstance& instance, long long cap, bool throw_on_cap)
      : in_(instance), lines_(singular_lines(instance)), sides_(lines_.size()), cap_(cap), throw_(throw_on_cap) {}

  double operator()(const double* x) {
    if (++count_ > cap_ && throw_) throw CappedOut{};
    for (std::size_t k = 0; k < lines_.size(); ++k) {
      const SingularLine& l = lines_[k];
      if (in_.dimension == 2 && !(x[1 - l.axis] < l.extent)) continue;
      if (x[l.axis] < l.at) sides_[k][0] = true;
      if (x[l.axis] > l.at) sides_[k][1] = true;
    }
    return in_(x);
  }
  long long count() const { return count_; }
  bool seen() const {
    for (const auto& s : sides_)
      if (!(s[0] && s[1])) return false;
    return true;
  }

 private:
  const GenzInstance& in_;
  std::vector<SingularLine> lines_;
  std::vector<std::array<bool, 2>> sides_;
  long long count_ = 0, cap_;
  bool throw_;
};

GenzRun judged(const std::string& who, const GenzInstance& in, double tolerance, double value, double estimate,
               const Counted& counted) {
  GenzRun r;
  r.competitor = who;
  r.tolerance = tolerance;
  r.error = static_cast<double>(std::abs(static_cast<long double>(value) - in.exact));
  r.estimate = estimate;
  r.resolution = kRoundingUlps * std::numeric_limits<double>::epsilon() * in.l1_norm();
  r.evaluations = counted.count();
  r.seen = counted.seen();
  return r;
}

/// The absolute target every competitor gets: the relative tolerance times |exact|.
double target(const GenzInstance& in, double tolerance) {
  return std::max(tolerance * static_cast<double>(std::abs(in.exact)), kEngineMinTolerance);
}

GenzRun run_ours(const GenzInstance& in, double tolerance, long long budget) {
  Counted counted(in, budget, false);
  CubatureOptions o;
  o.abs_tol = target(in, tolerance);
  o.max_evaluations = budget;
  Estimate e;
  if (in.dimension == 1) {
    const PanelIntegrand<1> f = [&](const std::array<std::span<const double>, 1>& nodes, std::span<double> values) {
      for (std::size_t m = 0; m < nodes[0].size(); ++m) values[m] = counted(&nodes[0][m]);
    };
    e = adaptive_cubature<1>(f, {std::vector<double>{0.0, 1.0}}, o);
  } else {
    const PanelIntegrand<2> f = [&](const std::array<std::span<const double>, 2>& nodes, std::span<double> values) {
      for (std::size_t a = 0; a < nodes[0].size(); ++a)
        for (std::size_t b = 0; b < nodes[1].size(); ++b) {
          const double x[2] = {nodes[0][a], nodes[1][b]};
          values[a * nodes[1].size() + b] = counted(x);
        }
    };
    e = adaptive_cubature<2>(f, {std::vector<double>{0.0, 1.0}, std::vector<double>{0.0, 1.0}}, o);
  }
  GenzRun r = judged("ours", in, tolerance, e.value, e.error, counted);
  r.claimed = e.converged;
  r.capped = !e.converged &&
             counted.count() + (in.dimension == 1 ? kBisectionEvaluations<1> : kBisectionEvaluations<2>) > budget;
  return r;
}

int libcubature_callback(unsigned, const double* x, void* data, unsigned, double* out) {
  *out = (*static_cast<Counted*>(data))(x);
  return 0;
}

GenzRun run_libcubature(const GenzInstance& in, double tolerance, long long budget, bool p_adaptive) {
  Counted counted(in, budget, false);
  const double lo[2] = {0.0, 0.0}, hi[2] = {1.0, 1.0};
  double value = 0.0, estimate = 0.0;
  auto integrate = p_adaptive ? pcubature : hcubature;
  const double abs_target = target(in, tolerance);
  const int status = integrate(1, libcubature_callback, &counted, static_cast<unsigned>(in.dimension), lo, hi,
                               static_cast<size_t>(budget), abs_target, 0.0, ERROR_INDIVIDUAL, &value, &estimate);
  GenzRun r = judged(p_adaptive ? "pcubature" : "hcubature", in, tolerance, value, estimate, counted);
  r.capped = counted.count() >= budget;
  r.claimed = status == 0 && !r.capped && estimate <= abs_target;
  return r;
}

/// Boost.Math's integrators, nested in 2-D (the inner ones at the same relative tolerance); the
/// estimate is the outer integral's, as a user reads it.
template <class Integrate1D>
GenzRun run_boost(const std::string& who, const GenzInstance& in, double tolerance, long long budget,
                  Integrate1D integrate) {
  Counted counted(in, budget, true);
  const double inf = std::numeric_limits<double>::infinity();
  GenzRun r = judged(who, in, tolerance, inf, inf, counted);
  try {
    double estimate = 0.0, value = 0.0;
    if (in.dimension == 1) {
      value = integrate([&](double x) { return counted(&x); }, tolerance, &estimate);
    } else {
      value = integrate(
          [&](double x) {
            return integrate(
                [&](double y) {
                  const double p[2] = {x, y};
                  return counted(p);
                },
                tolerance, nullptr);
          },
          tolerance, &estimate);
    }
    r = judged(who, in, tolerance, value, estimate, counted);
    r.claimed = std::isfinite(value) && estimate <= target(in, tolerance);
  } catch (const CappedOut&) {
    r.capped = true;
  } catch (const std::exception&) {  // e.g. tanh_sinh refusing a non-finite value
  }
  r.evaluations = counted.count();
  return r;
}

double boost_gauss_kronrod(const std::function<double(double)>& f, double tolerance, double* estimate) {
  return boost::math::quadrature::gauss_kronrod<double, 15>::integrate(f, 0.0, 1.0, 15, tolerance, estimate);
}

double boost_tanh_sinh(const std::function<double(double)>& f, double tolerance, double* estimate) {
  thread_local boost::math::quadrature::tanh_sinh<double> integrator;  // integrate() is not const
  return integrator.integrate(f, 0.0, 1.0, tolerance, estimate);
}

std::vector<GenzRun> run_instance(const GenzInstance& in, const GenzOptions& options) {
  std::vector<GenzRun> runs;
  for (double t : options.tolerances) {
    runs.push_back(run_ours(in, t, options.budget));
    runs.push_back(run_libcubature(in, t, options.budget, false));
    runs.push_back(run_libcubature(in, t, options.budget, true));
    runs.push_back(run_boost("boost_gauss_kronrod", in, t, options.budget, boost_gauss_kronrod));
    runs.push_back(run_boost("boost_tanh_sinh", in, t, options.budget, boost_tanh_sinh));
  }
  return runs;
}

void add(GenzCell& cell, const GenzRun& r) {
  ++cell.runs;
  cell.evaluations += r.evaluations;
  cell.log_evaluations += std::log(std::max<double>(1.0, static_cast<double>(r.evaluations)));
  if (r.capped) ++cell.capped;
  else if (!r.claimed) ++cell.not_converged;
  if (!r.dishonest()) return;
  const double ratio = r.error / (r.estimate + r.resolution);
  if (r.seen) {
    ++cell.dishonest;
    cell.worst_ratio = std::max(cell.worst_ratio, ratio);
  } else {
    ++cell.dishonest_unseen;
    cell.worst_unseen_ratio = std::max(cell.worst_unseen_ratio, ratio);
  }
}

}  // namespace

std::vector<GenzCell> run_genz_benchmark(const GenzOptions& options) {
  check_genz_options(options);
  std::vector<GenzCell> cells;
  for (int dimension : options.dimensions)
    for (GenzFamily family : kGenzFamilies) {
      std::mt19937_64 rng(options.seed + 1000u * dimension + index_of(family));
      std::vector<GenzInstance> instances;
      for (int k = 0; k < options.instances; ++k) instances.push_back(make_genz_instance(family, dimension, rng));
      std::vector<std::vector<GenzRun>> runs(instances.size());
      tbb::parallel_for(std::size_t{0}, instances.size(),
                        [&](std::size_t k) { runs[k] = run_instance(instances[k], options); });
      for (const std::string& who : genz_competitors()) {
        GenzCell cell;
        cell.family = family;
        cell.dimension = dimension;
        cell.competitor = who;
        for (const auto& per_instance : runs)
          for (const GenzRun& r : per_instance)
            if (r.competitor == who) add(cell, r);
        cells.push_back(cell);
      }
    }
  return cells;
}

namespace {

const GenzCell* find(const std::vector<GenzCell>& cells, GenzFamily family, int dimension, const std::string& who) {
  for (const GenzCell& c : cells)
    if (c.family == family && c.dimension == dimension && c.competitor == who) return &c;
  return nullptr;
}

/// One table: a row per family and dimension, a column per competitor, `cell` formatting each.
template <class Format>
void table(std::ostringstream& md, const std::vector<GenzCell>& cells, const GenzOptions& options, Format cell) {
  md << "| family | n |";
  for (const auto& who : genz_competitors()) md << " " << who << " |";
  md << "\n|---|---|";
  for (std::size_t k = 0; k < genz_competitors().size(); ++k) md << "---|";
  md << "\n";
  for (int dimension : options.dimensions)
    for (GenzFamily family : kGenzFamilies) {
      md << "| " << to_string(family) << " | " << dimension << " |";
      for (const auto& who : genz_competitors()) {
        const GenzCell* c = find(cells, family, dimension, who);
        md << " " << (c ? cell(*c) : std::string("—")) << " |";
      }
      md << "\n";
    }
}

/// Ours, summed over the families in `which` and every dimension.
GenzCell ours_total(const std::vector<GenzCell>& cells, const std::vector<GenzFamily>& which) {
  GenzCell total;
  for (const GenzCell& c : cells)
    if (c.competitor == "ours" && std::find(which.begin(), which.end(), c.family) != which.end()) {
      total.runs += c.runs;
      total.dishonest += c.dishonest;
      total.dishonest_unseen += c.dishonest_unseen;
      total.worst_ratio = std::max(total.worst_ratio, c.worst_ratio);
    }
  return total;
}

GenzCell competitor_total(const std::vector<GenzCell>& cells, GenzFamily family, const std::string& who) {
  GenzCell total;
  for (const GenzCell& c : cells)
    if (c.competitor == who && c.family == family) {
      total.runs += c.runs;
      total.dishonest += c.dishonest;
      total.dishonest_unseen += c.dishonest_unseen;
    }
  return total;
}

}  // namespace

std::string genz_markdown(const std::vector<GenzCell>& cells, const GenzOptions& options, const std::string& command,
                          double seconds) {
  std::ostringstream md;
  md << "## Genz's test families: the error estimate without hints\n\n"
     << "Generated by `" << command << "` (do not edit by hand); the run took " << number(seconds)
     << " s of wall time on " << util::machine_description() << ", shared with other work.\n\n"
     << "Genz's six families (A. Genz, \"A package for testing multiple integration subroutines\", 1987; "
        "TESTPACK's difficulty levels: Σ aᵢ = 110/n^1.5, 600/n², 600/n², 100/n, 150/n², 100/n²), "
     << options.instances << " seeded random instances per family in 1-D and 2-D on the unit box, each at the "
     << "relative tolerances";
  for (double t : options.tolerances) md << " " << number(t);
  md << ", with their closed-form integrals (long double). Every competitor integrates the same integrand "
        "through one counting wrapper to the same absolute target (relative tolerance × |exact|) within "
     << options.budget
     << " evaluations: ours with no hints (the box's ends as its only cuts, as a user's own integrand), "
        "hcubature and pcubature (libcubature), Boost.Math's adaptive gauss_kronrod<15> and tanh_sinh (nested in "
        "2-D; their estimate is the outer integral's). A run is *dishonest* when it claims the target (converged, "
        "or its estimate within it) and |value − exact| exceeds its estimate by more than "
     << number(kRoundingUlps)
     << " ulps of the integrand's L1 norm. C0 bends and the discontinuous family jumps on lines; a run in which "
        "some such line had no evaluated point on one of its sides (the line lies between the box's end and the "
        "nodes nearest to it) is *unseen*: no rule can tell the integrand there from its smooth continuation. "
        "Cells below: dishonest runs that saw every line, + those that did not (unseen), of the cell's runs.\n\n";
  md << "### Dishonest runs (seen + unseen)\n\n";
  table(md, cells, options, [](const GenzCell& c) {
    return std::to_string(c.dishonest) + " + " + std::to_string(c.dishonest_unseen) + " (" +
           percent(c.dishonest + c.dishonest_unseen, c.runs) + ")";
  });
  md << "\n### Worst error / estimate of a dishonest run (seen; unseen)\n\n";
  table(md, cells, options, [](const GenzCell& c) {
    return (c.dishonest ? number(c.worst_ratio) : std::string("–")) + "; " +
           (c.dishonest_unseen ? number(c.worst_unseen_ratio) : std::string("–"));
  });
  md << "\n### Not converged (said so within the budget) + over the budget\n\n";
  table(md, cells, options,
        [](const GenzCell& c) { return percent(c.not_converged, c.runs) + " + " + percent(c.capped, c.runs); });
  md << "\n### Evaluations (geometric mean over the runs)\n\n";
  table(md, cells, options, [](const GenzCell& c) { return number(c.geometric_mean_evaluations()); });

  const GenzCell smooth = ours_total(
      cells, {GenzFamily::oscillatory, GenzFamily::product_peak, GenzFamily::corner_peak, GenzFamily::gaussian});
  const GenzCell c0 = ours_total(cells, {GenzFamily::c0});
  const GenzCell jumps = competitor_total(cells, GenzFamily::discontinuous, "ours");
  const GenzCell hcubature_jumps = competitor_total(cells, GenzFamily::discontinuous, "hcubature");
  const double ours_rate = jumps.runs ? double(jumps.dishonest + jumps.dishonest_unseen) / jumps.runs : 0.0;
  const double hcubature_rate =
      hcubature_jumps.runs ? double(hcubature_jumps.dishonest + hcubature_jumps.dishonest_unseen) / hcubature_jumps.runs
                           : 0.0;
  auto verdict = [](bool met) { return met ? "**met**" : "**missed**"; };
  const double loosest = *std::max_element(options.tolerances.begin(), options.tolerances.end());
  const double tightest = *std::min_element(options.tolerances.begin(), options.tolerances.end());
  const std::vector<double> every_decade = GenzOptions{}.tolerances;
  const auto ran = [&](double t) {
    return std::find(options.tolerances.begin(), options.tolerances.end(), t) != options.tolerances.end();
  };
  const std::size_t decades_ran = std::count_if(every_decade.begin(), every_decade.end(), ran);
  md << "\n### Targets, met or missed\n\n"
     << "- The sample: ≥ " << kGenzInstancesTarget
     << " instances per family and dimension, each at every relative tolerance 1e-3, 1e-4, …, 1e-12: "
     << verdict(options.instances >= kGenzInstancesTarget && decades_ran == every_decade.size()) << " ("
     << options.instances << " instances; " << decades_ran << " of the " << every_decade.size() << " tolerances, "
     << number(loosest) << " … " << number(tightest) << "). The verdicts below hold for this sample only.\n"
     << "- Oscillatory, product peak, corner peak, Gaussian and C0, 1-D and 2-D, no hints: 0 dishonest runs. "
     << "Oscillatory, product peak, corner peak, Gaussian: " << verdict(smooth.dishonest + smooth.dishonest_unseen == 0)
     << " (" << smooth.dishonest + smooth.dishonest_unseen << " of " << smooth.runs
     << "). C0: " << verdict(c0.dishonest + c0.dishonest_unseen == 0) << " (" << c0.dishonest << " of " << c0.runs
     << " where every kink was seen, and " << c0.dishonest_unseen
     << " where one lay between the box's end and the nodes, shown apart).\n"
     << "- Discontinuous: dishonest only where no node met the jump: " << verdict(jumps.dishonest == 0) << " ("
     << jumps.dishonest << " seen, " << jumps.dishonest_unseen << " unseen, of " << jumps.runs
     << " runs); at most hcubature's rate: " << verdict(ours_rate <= hcubature_rate) << " (ours "
     << number(100 * ours_rate, 2) << "%, hcubature " << number(100 * hcubature_rate, 2) << "%).\n";
  return md.str();
}

}  // namespace ganzfeld::bench
