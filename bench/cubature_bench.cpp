#include "bench/cubature_bench.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <thread>

#include <cubature.h>
#include <tbb/parallel_for.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/math/special_functions/legendre.hpp>

#include "integrate/laws.h"
#include "models/spec.h"
#include "reference/lune_reference.h"
#include "reports/plot.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::bench {

namespace {

using std::numbers::pi;

struct Case {
  ModelPtr model;
  Vec3 i, j;  // sky pole and view
  Vec3 lobe;  // where the integrand peaks (break points of the Boost reference)
};

/// The one integrand wrapper every competitor goes through: counts evaluations and enforces
/// the cap (by exception for C++ integrators; libcubature gets the cap as maxEval).
struct CappedOut {};
struct Integrand {
  const Case* c;
  Lune lune;
  long long count = 0, cap = 0;
  bool throw_on_cap = true;

  void tick() {
    if (++count > cap && throw_on_cap) throw CappedOut{};
  }
  /// (k·n) f(k, j) cos t on the lune rectangle.
  double lune_point(double t, double phi) {
    tick();
    const Vec3 k = lune.direction(t, phi);
    return std::cos(t) * std::max(k.z, 0.0) * c->model->f(k, c->j);
  }
  /// (k·n) f(k, j) sin theta [k·i > 0] on the hemisphere rectangle (the naive way).
  double hemisphere_point(double theta, double phi) {
    tick();
    const Vec3 k = direction(theta, phi);
    if (glm::dot(k, c->i) <= 0.0) return 0.0;
    return std::sin(theta) * std::max(k.z, 0.0) * c->model->f(k, c->j);
  }
};

/// Our engine's evaluations counted the way the peers' are: by the calls that reach f, not by the
/// engine's own report. With `hints` false the model's mass hints are hidden from the engine, so
/// it gets only what the peers get (the integrand).
class CountingModel final : public Model {
 public:
  CountingModel(const Model& model, bool hints) : model_(model), hints_(hints) {}
  std::string spec() const override { return model_.spec(); }
  Traits traits() const override { return model_.traits(); }
  double f(const Vec3& i, const Vec3& j) const noexcept override {
    count_.fetch_add(1, std::memory_order_relaxed);
    return model_.f(i, j);
  }
  void f_batch(std::span<const Vec3> i, std::span<const Vec3> j, std::span<double> out) const noexcept override {
    count_.fetch_add(static_cast<long long>(i.size()), std::memory_order_relaxed);
    model_.f_batch(i, j, out);
  }
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override {
    return hints_ ? model_.mass_hints(fixed, varying) : MassHints{};
  }
  long long count() const { return count_.load(); }

 private:
  const Model& model_;
  bool hints_;
  mutable std::atomic<long long> count_{0};
};

// ---------------------------------------------------------------------------------------------
// Families of integrands (seeded).

Vec3 random_unit_orthogonal(const Vec3& v, std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Vec3 q{g(rng), g(rng), g(rng)};
  q -= glm::dot(q, v) * v;
  return glm::normalize(q);
}

/// A pole i whose sky edge (the great circle ⊥ i) lies at signed angular distance delta from
/// `lobe` (delta > 0: the lobe is inside the lune's k·i > 0 side).
Vec3 pole_at_distance(const Vec3& lobe, double delta, std::mt19937_64& rng) {
  const Vec3 q = random_unit_orthogonal(lobe, rng);
  return std::sin(delta) * lobe + std::cos(delta) * q;
}

struct Family {
  std::string name;
  std::function<Case(std::mt19937_64&, int)> make;
};

std::vector<Family> families() {
  auto lobe_family = [](std::string name, bool mirror_lobe) {
    return Family{name, [name, mirror_lobe](std::mt19937_64& rng, int k) {
                    std::uniform_real_distribution<double> u(0.0, 1.0);
                    const double alphas[] = {1, 10, 100, 1000};
                    const double alpha = alphas[k % 4];
                    const double w = std::sqrt(2.0 / alpha);
                    const Vec3 j = direction_from_cos(0.05 + 0.95 * u(rng), 2 * pi * u(rng));
                    const Vec3 lobe = mirror_lobe ? mirror(j) : j;
                    double delta;
                    switch ((k / 4) % 3) {
                      case 0: delta = 0.3 + 0.9 * u(rng); break;                   // inside
                      case 1: delta = (4 * u(rng) - 2) * std::min(w, 0.3); break;  // near the sky edge
                      default: delta = -(0.3 + 0.9 * u(rng)); break;               // outside
                    }
                    return Case{parse_model(name + ":alpha=" + std::to_string(int(alpha))),
                                pole_at_distance(lobe, delta, rng), j, lobe};
                  }};
  };
  return {
      lobe_family("specular", true),
      lobe_family("backscatter", false),
      {"minnaert",
       [](std::mt19937_64& rng, int k) {
         std::uniform_real_distribution<double> u(0.0, 1.0);
         const char* xi[] = {"0.3", "1", "2.7"};
         const Vec3 j = direction_from_cos(u(rng), 2 * pi * u(rng));
         return Case{parse_model(std::string("minnaert:xi=") + xi[k % 3]),
                     direction_from_cos(2 * u(rng) - 1, 2 * pi * u(rng)), j, Vec3{0, 0, 1}};
       }},
      {"asperity",
       [](std::mt19937_64& rng, int k) {
         std::uniform_real_distribution<double> u(0.0, 1.0);
         const int alphas[] = {1, 10, 100, 1000};
         const Vec3 j = direction_from_cos(0.01 + 0.99 * u(rng), 2 * pi * u(rng));
         return Case{parse_model("asperity:alpha=" + std::to_string(alphas[k % 4])),
                     direction_from_cos(2 * u(rng) - 1, 2 * pi * u(rng)), j,
                     direction_from_cos(0.0, std::atan2(j.y, j.x))};
       }},
      {"degenerate",
       [](std::mt19937_64& rng, int k) {
         std::uniform_real_distribution<double> u(0.0, 1.0);
         const char* specs[] = {"specular:alpha=10", "minnaert:xi=0.3", "asperity:alpha=4"};
         const double poles[] = {1.0 - 1e-12, 1.0, -1.0 + 1e-6, -0.999, 1e-6};
         const double views[] = {0.0, 1e-6, 1.0};
         const Vec3 j = direction_from_cos(views[k % 3], 2 * pi * u(rng));
         const ModelPtr m = parse_model(specs[k % 3]);
         return Case{m, direction_from_cos(poles[(k / 3) % 5], 2 * pi * u(rng)), j, mirror(j)};
       }},
      {"perfect-backscatter",
       [](std::mt19937_64& rng, int k) {
         std::uniform_real_distribution<double> u(0.0, 1.0);
         const int alphas[] = {2, 10, 100};
         const Vec3 j = direction_from_cos(1e-3 * u(rng), 2 * pi * u(rng));
         return Case{parse_model("perfect-backscatter:alpha=" + std::to_string(alphas[k % 3])),
                     direction_from_cos(2e-3 * u(rng) - 1e-3, 2 * pi * u(rng)), j, j};
       }},
  };
}

// ---------------------------------------------------------------------------------------------
// Competitors.

using BreakPoints = std::array<std::vector<double>, 2>;

/// Independent reference (reference/): Boost gauss_kronrod<61>, nested, with break points at the
/// lobe, to a relative 1e-12 at depth 6, on the same rectangle as ours (the hemisphere's edge axis
/// as our lune puts it, so that both see the same coordinates).
reference::Value boost_reference(const Case& c, const Lune& lune) {
  reference::Options options;
  options.tolerance = 1e-12;
  options.max_depth = 6;
  options.global_tolerance = false;  // as the benchmark's figures were made
  const reference::LuneCoordinates coordinates(c.i, lune.e);
  const auto [t_lobe, phi_lobe] = coordinates.coordinates(c.lobe);
  return reference::lune_integral([&](const Vec3& k) { return c.model->f(k, c.j); }, coordinates,
                                  reference::cuts(-pi / 2, pi / 2, {t_lobe}),
                                  reference::cuts(coordinates.psi_lo, coordinates.psi_hi, {phi_lobe}), options);
}

int cubature_callback(unsigned, const double* x, void* data, unsigned, double* out) {
  auto* in = static_cast<std::pair<Integrand*, bool>*>(data);
  *out = in->second ? in->first->hemisphere_point(x[0], x[1]) : in->first->lune_point(x[0], x[1]);
  return 0;
}

Run run_libcubature(const Case& c, const Lune& lune, double tol, long long cap, bool naive, bool p_adaptive,
                    const Reference& ref) {
  Integrand in{&c, lune, 0, cap, false};
  std::pair<Integrand*, bool> data{&in, naive};
  const double lo_lune[2] = {-pi / 2, lune.phi_lo}, hi_lune[2] = {pi / 2, pi / 2};
  const double lo_hemi[2] = {0.0, 0.0}, hi_hemi[2] = {pi / 2, 2 * pi};
  double value = 0.0, error = 0.0;
  const util::Stopwatch start;
  auto fn = p_adaptive ? pcubature : hcubature;
  const int status = fn(1, cubature_callback, &data, 2, naive ? lo_hemi : lo_lune, naive ? hi_hemi : hi_lune,
                        static_cast<size_t>(cap), tol, 0.0, ERROR_INDIVIDUAL, &value, &error);
  Run r =
      measured(naive ? "hcubature_naive" : (p_adaptive ? "pcubature_lune" : "hcubature_lune"), value, error, tol, ref);
  r.seconds = start.seconds();
  r.evaluations = in.count;
  r.capped = in.count >= cap;
  r.claimed = status == 0 && !r.capped && error <= tol;
  return r;
}

template <class Nested>
Run run_boost(const std::string& name, const Case& c, const Lune& lune, double tol, long long cap, const Reference& ref,
              Nested nested) {
  Integrand in{&c, lune, 0, cap, true};
  // No value: the error is infinite (and the estimate too, so that no verdict calls it dishonest).
  const double inf = std::numeric_limits<double>::infinity();
  Run r = measured(name, inf, inf, tol, ref);
  const util::Stopwatch start;
  try {
    double estimate = 0.0;
    const double value = nested(in, tol, estimate);
    r = measured(name, value, estimate, tol, ref);
    r.claimed = r.estimate <= tol;
  } catch (const CappedOut&) {
    r.capped = true;
  } catch (const std::exception&) {  // e.g. tanh_sinh refusing a non-finite value
  }
  r.seconds = start.seconds();
  r.evaluations = in.count;
  return r;
}

// The nested peers report the outer integral's error estimate (Boost's own), as a user would read it.
double nested_gauss_kronrod(Integrand& in, double tol, double& estimate) {
  using boost::math::quadrature::gauss_kronrod;
  return gauss_kronrod<double, 15>::integrate(
      [&](double t) {
        return gauss_kronrod<double, 15>::integrate([&](double phi) { return in.lune_point(t, phi); }, in.lune.phi_lo,
                                                    pi / 2, 15, tol);
      },
      -pi / 2, pi / 2, 15, tol, &estimate);
}

double nested_tanh_sinh(Integrand& in, double tol, double& estimate) {
  boost::math::quadrature::tanh_sinh<double> ts;
  return ts.integrate(
      [&](double t) {
        return ts.integrate([&](double phi) { return in.lune_point(t, phi); }, in.lune.phi_lo, pi / 2, tol);
      },
      -pi / 2, pi / 2, tol, &estimate);
}

/// Gauss–Legendre nodes and weights on [-1, 1] for any n (Boost's Legendre zeros).
struct GaussLegendre {
  std::vector<double> x, w;
};
const GaussLegendre& gauss_legendre(int n) {
  static std::mutex mutex;
  static std::map<int, GaussLegendre> cache;
  std::lock_guard lock(mutex);
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  GaussLegendre gl;
  for (double z : boost::math::legendre_p_zeros<double>(n)) {
    const double dp = boost::math::legendre_p_prime(n, z);
    const double weight = 2.0 / ((1.0 - z * z) * dp * dp);
    gl.x.push_back(z);
    gl.w.push_back(weight);
    if (z != 0.0) {
      gl.x.push_back(-z);
      gl.w.push_back(weight);
    }
  }
  return cache.emplace(n, gl).first->second;
}

/// The oracle: composite n×n Gauss–Legendre on our initial grid, n as small as hindsight allows.
Run run_oracle(const Case& c, const Lune& lune, const BreakPoints& cuts, double target, const Reference& ref) {
  Run r;
  r.competitor = "oracle";
  r.tolerance = target;
  r.resolution = ref.resolution();
  const util::Stopwatch start;
  for (int n : {2, 3, 4, 5, 6, 7, 8, 10, 12, 14, 16, 20, 24, 28, 32, 40, 48, 64, 80, 96, 128, 160, 192, 256}) {
    const GaussLegendre& gl = gauss_legendre(n);
    Integrand in{&c, lune, 0, std::numeric_limits<long long>::max(), false};
    double sum = 0.0;
    for (std::size_t a = 0; a + 1 < cuts[0].size(); ++a)
      for (std::size_t b = 0; b + 1 < cuts[1].size(); ++b) {
        const double ht = 0.5 * (cuts[0][a + 1] - cuts[0][a]), ct = 0.5 * (cuts[0][a + 1] + cuts[0][a]);
        const double hp = 0.5 * (cuts[1][b + 1] - cuts[1][b]), cp = 0.5 * (cuts[1][b + 1] + cuts[1][b]);
        for (std::size_t p = 0; p < gl.x.size(); ++p)
          for (std::size_t q = 0; q < gl.x.size(); ++q)
            sum += ht * hp * gl.w[p] * gl.w[q] * in.lune_point(ct + ht * gl.x[p], cp + hp * gl.x[q]);
      }
    r.evaluations = in.count;
    r.achieved_error = std::abs(sum - ref.value);
    if (r.achieved_error <= target) break;
  }
  r.capped = r.achieved_error > target;
  r.seconds = start.seconds();
  return r;
}

/// Monte Carlo as real-time engines bake: cosine-weighted directions, estimator pi f [k·i > 0].
Run run_monte_carlo(const Case& c, double budget_seconds, const Reference& ref, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto sample = [&] {
    const double r1 = u(rng), r2 = u(rng);
    const double s = std::sqrt(r1);
    const Vec3 k{s * std::cos(2 * pi * r2), s * std::sin(2 * pi * r2), std::sqrt(std::max(0.0, 1.0 - r1))};
    return glm::dot(k, c.i) > 0.0 ? pi * c.model->f(k, c.j) : 0.0;
  };
  // Calibrate the cost per sample, then spend the same wall time as ours.
  const util::Stopwatch start;
  long long n = 0;
  double sum = 0.0;
  do {
    for (int k = 0; k < 1000; ++k) sum += sample();
    n += 1000;
  } while (start.seconds() < budget_seconds && n < 100'000'000);
  Run r;
  r.competitor = "mc";
  r.resolution = ref.resolution();
  r.evaluations = n;
  r.seconds = start.seconds();
  r.achieved_error = std::abs(sum / n - ref.value);  // no floor: MC's error is what it is
  return r;
}

/// Cheapest run of a competitor that reaches `target`; the cap (a lower bound) if none does.
std::pair<double, bool> cost_to_reach(const std::vector<Run>& runs, const std::string& who, double target,
                                      long long cap) {
  double best = std::numeric_limits<double>::infinity();
  for (const Run& r : runs)
    if (r.competitor == who && r.achieved_error <= target && !r.capped) best = std::min(best, double(r.evaluations));
  if (std::isfinite(best)) return {best, false};
  return {double(cap), true};
}

}  // namespace

double Reference::resolution() const {
  return error + doubt + kRoundingUlps * std::numeric_limits<double>::epsilon() * std::abs(value);
}

Run measured(const std::string& competitor, double value, double estimate, double tolerance,
             const Reference& reference) {
  Run r;
  r.competitor = competitor;
  r.tolerance = tolerance;
  r.estimate = estimate;
  r.achieved_error = std::abs(value - reference.value);  // no floor: see resolution()
  r.resolution = reference.resolution();
  return r;
}

// The resolution is added to the bound, never to (nor as a floor under) the error: an error the
// references cannot tell from 0 passes any bound, a real one is judged as measured.
Verdict judge(const Run& run) {
  return {run.achieved_error > run.tolerance + run.resolution, run.achieved_error > run.estimate + run.resolution};
}

double Miss::excess() const { return achieved_error / (std::min(tolerance, estimate) + resolution); }

bool CubatureBenchOptions::runs(const std::string& competitor) const {
  return competitors.empty() || std::find(competitors.begin(), competitors.end(), competitor) != competitors.end();
}

const std::vector<std::string>& cubature_competitors() {
  static const std::vector<std::string> names{
      "ours",           "ours_no_hints",       "oracle",         "mc", "hcubature_lune", "hcubature_naive",
      "pcubature_lune", "boost_gauss_kronrod", "boost_tanh_sinh"};
  return names;
}

CubatureBenchOptions quick_options() {
  return {.cases_per_family = 4, .tolerances = {1e-6, 1e-10}, .competitor_cap = 200'000};
}

namespace {

/// The peers whose evaluations are compared with ours (ratio = theirs / ours).
const std::vector<std::string> kPeers{"ours_no_hints",   "oracle",         "hcubature_lune",
                                      "hcubature_naive", "pcubature_lune", "boost_gauss_kronrod",
                                      "boost_tanh_sinh"};

/// Everything measured on one case: every competitor's runs, the evaluation ratios at the ratio
/// tolerance, Monte Carlo at our wall time, failures per competitor, and our missed/dishonest runs.
struct CaseResult {
  bool skipped = false;
  std::vector<Run> runs;
  std::map<std::string, std::pair<double, bool>> ratio;  // (ratio, capped)
  std::optional<double> mc_ratio;                        // none when both MC and ours are exact
  int missed = 0, dishonest = 0, ours = 0;
  std::vector<Miss> misses;
  std::map<std::string, Failures> failures;
  std::optional<Disagreement> disagreement;
};

/// Our run at `tol` through the counting wrapper, capped like the peers.
Run run_ours(const Case& c, double tol, long long cap, const Reference& ref, bool hints) {
  const CountingModel counted(*c.model, hints);
  CubatureOptions o;
  o.abs_tol = tol;
  o.max_evaluations = cap;
  const util::Stopwatch start;
  const Estimate e = vignetting(counted, c.i, c.j, o);
  Run r = measured(hints ? "ours" : "ours_no_hints", e.value, e.error, tol, ref);
  r.seconds = start.seconds();
  r.evaluations = counted.count();
  r.claimed = e.converged;
  r.capped = !e.converged && counted.count() >= cap;
  return r;
}

/// Counts a run's failure and its verdicts (judge(): beyond the case's resolution).
void count_failure(const Run& r, std::map<std::string, Failures>& failures) {
  Failures& f = failures[r.competitor];
  const Verdict v = judge(r);
  ++f.runs;
  f.missed += v.missed;
  f.dishonest += v.dishonest;
  if (r.capped) ++f.over_cap;
  else if (!r.claimed) ++f.not_converged;
  else if (v.missed) ++f.silently_wrong;
}

/// Ours: missed (error above the tolerance) or dishonest (error above the estimate), beyond the
/// case's resolution; each such run is kept with its case, to be reproduced with `ganzfeld eval`.
void judge_ours(const Case& c, const Run& r, CaseResult& out) {
  ++out.ours;
  const Verdict v = judge(r);
  out.missed += v.missed;
  out.dishonest += v.dishonest;
  if (v.missed || v.dishonest)
    out.misses.push_back({c.model->spec(),
                          {c.i.x, c.i.y, c.i.z},
                          {c.j.x, c.j.y, c.j.z},
                          r.tolerance,
                          r.achieved_error,
                          r.estimate,
                          r.resolution,
                          r.evaluations});
}

/// The references of a case: Boost GK61 (independent, the one every competitor is judged by) and
/// ours at 1e-13; their difference is the doubt every verdict allows.
Reference references(const Case& c, const Lune& lu, CaseResult& out) {
  CubatureOptions ref_options;
  ref_options.abs_tol = 1e-13;
  ref_options.max_evaluations = 500'000'000;
  const double ours = vignetting(*c.model, c.i, c.j, ref_options).value;
  const reference::Value boost = boost_reference(c, lu);
  if (std::abs(ours - boost.value) > kReferenceAgreement)
    out.disagreement = Disagreement{c.model->spec(), {c.i.x, c.i.y, c.i.z}, {c.j.x, c.j.y, c.j.z}, boost.value, ours};
  return {boost.value, std::abs(ours - boost.value), boost.total_error()};
}

CaseResult run_case(const Case& c, const CubatureBenchOptions& options, std::uint64_t mc_seed) {
  CaseResult out;
  const Lune lu = lune(c.i, c.j);
  if (lu.empty) {  // no sky above the surface here: g = 0 exactly, nothing to integrate
    out.skipped = true;
    return out;
  }
  const Reference ref = references(c, lu, out);
  const long long cap = options.competitor_cap;
  for (double tol : options.tolerances) {
    std::vector<Run> runs;
    if (options.runs("ours")) runs.push_back(run_ours(c, tol, cap, ref, true));
    if (options.runs("ours_no_hints")) runs.push_back(run_ours(c, tol, cap, ref, false));
    if (options.runs("hcubature_lune")) runs.push_back(run_libcubature(c, lu, tol, cap, false, false, ref));
    if (options.runs("hcubature_naive")) runs.push_back(run_libcubature(c, lu, tol, cap, true, false, ref));
    if (options.runs("pcubature_lune")) runs.push_back(run_libcubature(c, lu, tol, cap, false, true, ref));
    if (options.runs("boost_gauss_kronrod"))
      runs.push_back(run_boost("boost_gauss_kronrod", c, lu, tol, cap, ref, nested_gauss_kronrod));
    if (options.runs("boost_tanh_sinh"))
      runs.push_back(run_boost("boost_tanh_sinh", c, lu, tol, cap, ref, nested_tanh_sinh));
    for (const Run& r : runs) {
      if (r.competitor == "ours") judge_ours(c, r, out);
      count_failure(r, out.failures);
    }
    out.runs.insert(out.runs.end(), runs.begin(), runs.end());
  }
  if (!options.runs("ours")) return out;  // ratios and Monte Carlo are relative to ours
  const double target = options.ratio_tolerance;
  const double ours_cost = cost_to_reach(out.runs, "ours", target, cap).first;
  if (options.runs("oracle"))
    out.runs.push_back(run_oracle(c, lu, lune_cuts(*c.model, lu, c.j, Varying::incident), target, ref));
  for (const auto& who : kPeers) {
    if (!options.runs(who)) continue;
    const auto [cost, capped] = cost_to_reach(out.runs, who, target, cap);
    out.ratio[who] = {cost / ours_cost, capped};
  }
  if (!options.runs("mc")) return out;
  // Monte Carlo with our wall time at the ratio tolerance. Neither error is floored; ours counts
  // as at least the case's resolution, below which it is not measured (a smaller divisor would
  // inflate the ratio). Both exact (0 / 0) leaves the ratio undefined: the case is left out.
  for (const Run& r : std::vector<Run>(out.runs))
    if (r.competitor == "ours" && r.tolerance == target) {
      const Run mc = run_monte_carlo(c, std::max(r.seconds, 1e-4), ref, mc_seed);
      out.runs.push_back(mc);
      const double ours = std::max(r.achieved_error, r.resolution);
      if (ours > 0.0 && mc.achieved_error > 0.0) out.mc_ratio = mc.achieved_error / ours;
    }
  return out;
}

/// A family's figures from its cases: geometric-mean ratios, capped counts, our miss rates.
FamilyResult summarize(const std::string& name, const std::vector<CaseResult>& per_case) {
  FamilyResult fr;
  fr.name = name;
  std::map<std::string, double> log_sum;
  double mc_log_sum = 0.0;
  int mc_cases = 0;
  int total_ours = 0, missed = 0, dishonest = 0;
  for (const CaseResult& cr : per_case) {
    if (cr.skipped) {
      ++fr.skipped;
      continue;
    }
    ++fr.cases;
    total_ours += cr.ours;
    missed += cr.missed;
    dishonest += cr.dishonest;
    for (const auto& [who, rc] : cr.ratio) {
      log_sum[who] += std::log(rc.first);
      if (rc.second) ++fr.capped[who];
    }
    if (cr.mc_ratio) mc_log_sum += std::log(*cr.mc_ratio), ++mc_cases;
    fr.runs.insert(fr.runs.end(), cr.runs.begin(), cr.runs.end());
    fr.misses.insert(fr.misses.end(), cr.misses.begin(), cr.misses.end());
    for (const auto& [who, f] : cr.failures) {
      Failures& sum = fr.failures[who];
      sum.runs += f.runs, sum.silently_wrong += f.silently_wrong, sum.not_converged += f.not_converged,
          sum.over_cap += f.over_cap, sum.missed += f.missed, sum.dishonest += f.dishonest;
    }
    if (cr.disagreement) fr.disagreements.push_back(*cr.disagreement);
  }
  if (fr.cases > 0) {
    for (const auto& [who, s] : log_sum) fr.evals_ratio[who] = std::exp(s / fr.cases);
    fr.mc_error_ratio_equal_time = mc_cases ? std::exp(mc_log_sum / mc_cases) : 0.0;
    fr.missed_rate = double(missed) / total_ours;
    fr.dishonest_rate = double(dishonest) / total_ours;
  }
  return fr;
}

}  // namespace

std::vector<FamilyResult> run_cubature_benchmark(const CubatureBenchOptions& options) {
  std::vector<FamilyResult> results;
  for (const Family& family : families()) {
    std::mt19937_64 rng(options.seed);
    std::vector<Case> cases;
    for (int k = 0; k < options.cases_per_family; ++k) cases.push_back(family.make(rng, k));
    std::vector<CaseResult> per_case(cases.size());
    tbb::parallel_for(std::size_t{0}, cases.size(),
                      [&](std::size_t k) { per_case[k] = run_case(cases[k], options, options.seed + k); });
    results.push_back(summarize(family.name, per_case));
  }
  return results;
}

namespace {

const std::vector<std::string> kCompetitors{"ours",
                                            "ours_no_hints",
                                            "oracle",
                                            "hcubature_lune",
                                            "pcubature_lune",
                                            "hcubature_naive",
                                            "boost_gauss_kronrod",
                                            "boost_tanh_sinh"};

/// (geometric mean evaluations, geometric mean achieved error) per competitor and tolerance.
std::map<std::string, std::vector<std::pair<double, double>>> work_precision(
    const std::vector<FamilyResult>& families) {
  std::map<std::string, std::map<double, std::array<double, 3>>> acc;  // log evals, log error, count
  for (const auto& f : families)
    for (const Run& r : f.runs) {
      if (r.competitor == "mc" || r.competitor == "oracle" || !std::isfinite(r.achieved_error) || r.evaluations <= 0)
        continue;
      auto& a = acc[r.competitor][r.tolerance];
      a[0] += std::log(double(r.evaluations));
      // A geometric mean cannot take an exact 0: an error below the case's resolution is plotted
      // at the resolution (what it is measured to), the same rule as the Monte Carlo ratio's.
      a[1] += std::log(std::max({r.achieved_error, r.resolution, std::numeric_limits<double>::min()}));
      a[2] += 1;
    }
  std::map<std::string, std::vector<std::pair<double, double>>> out;
  for (const auto& [who, by_tol] : acc)
    for (auto it = by_tol.rbegin(); it != by_tol.rend(); ++it)  // loose to tight
      out[who].push_back({std::exp(it->second[0] / it->second[2]), std::exp(it->second[1] / it->second[2])});
  return out;
}

std::string number(double x, int digits = 3) { return significant(x, digits); }

}  // namespace

std::string percent(int part, int whole) {
  if (!whole) return "—";
  const double p = 100.0 * part / whole;
  // Two significant digits below 10%, whole percents above (100% stays "100%", not "1e+02%").
  return (p < 10.0 ? significant(p, 2) : std::to_string(std::lround(p))) + "%";
}

namespace {

std::string ratio_cell(const FamilyResult& f, const char* who) {
  const auto it = f.evals_ratio.find(who);
  if (it == f.evals_ratio.end()) return "—";
  const auto capped = f.capped.find(who);
  return (capped != f.capped.end() && capped->second > 0 ? "≥ " : "") + number(it->second);
}

std::string spread(const std::vector<double>& seconds) {
  const auto [lo, hi] = std::minmax_element(seconds.begin(), seconds.end());
  return number(util::median(seconds)) + " s [" + number(*lo) + "–" + number(*hi) + "]";
}

void method_section(std::ostringstream& md, const CubatureBenchOptions& options, const std::string& command) {
  md << "One run of `" << command << "` on " << util::machine_description() << " (read from the machine). "
     << "Every competitor integrates the same integrand (the law of vignetting, (k·n) f(k, j) over the lune of "
        "sky pole i) with the same absolute tolerances (";
  for (double t : options.tolerances) md << number(t) << " ";
  md << ") and the same cap of " << options.competitor_cap
     << " evaluations, counted by the same kind of wrapper: a counting integrand for the peers, a counting "
        "model around f for ours (not the engine's own report).\n\n"
        "**Reference.** Every case is judged against Boost gauss_kronrod<61>, nested, with break points at the "
        "lobe, written in reference/ apart from integrate/ (it shares only the lune's parametrization). Ours at "
        "1e-13 is computed too; where the two differ by more than "
     << number(kReferenceAgreement)
     << " the case is kept and listed below.\n\n"
        "**Verdicts.** Achieved errors are |value − reference|, never floored. A run *missed* when its error "
        "exceeds the requested tolerance, and is *dishonest* when it exceeds the run's own error estimate, each "
        "beyond the case's resolution: the reference's own stated error (Boost's estimates) plus the references' "
        "difference plus "
     << number(kRoundingUlps)
     << " ulps of |reference| (the rounding the engine allows for its own sums, granted to the reference; the "
        "integrands are nonnegative, so |reference| is their L1 norm). So an answer exact to rounding on a value "
        "of about 0 is not called dishonest for stating a tinier estimate, and no competitor is blamed for a "
        "doubtful reference.\n\n"
        "**Ratios** are (competitor's evaluations) / (ours) to reach an achieved error ≤ "
     << number(options.ratio_tolerance)
     << ", each taking its cheapest run that does (geometric mean over the cases); a competitor that never gets "
        "there within the cap is charged the cap, so its ratio is a lower bound (marked ≥). *ours, no hints* is "
        "our engine with the model's mass hints hidden: the information the peers get. The *oracle* is the "
        "cheapest *uniform* composite Gauss–Legendre rule on our initial grid (our cuts), n chosen in hindsight: "
        "what a well-placed fixed rule costs, not a lower bound for adaptive rules. *MC error ratio* is "
        "(Monte Carlo error) / (ours) at equal wall time, neither floored; ours counts as at least the case's "
        "resolution, below which it is not measured (cases where both are exact are left out).\n\n";
}

void ratio_table(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  md << "| family | cases | skipped | refs disagree | ours, no hints | oracle | hcubature lune | pcubature lune | "
        "hcubature naive | Boost GK | Boost tanh-sinh | MC error ratio |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& f : families)
    md << "| " << f.name << " | " << f.cases << " | " << f.skipped << " | " << f.disagreements.size() << " | "
       << ratio_cell(f, "ours_no_hints") << " | " << ratio_cell(f, "oracle") << " | " << ratio_cell(f, "hcubature_lune")
       << " | " << ratio_cell(f, "pcubature_lune") << " | " << ratio_cell(f, "hcubature_naive") << " | "
       << ratio_cell(f, "boost_gauss_kronrod") << " | " << ratio_cell(f, "boost_tanh_sinh") << " | "
       << number(f.mc_error_ratio_equal_time, 2) << " |\n";
}

void failure_table(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  md << "\n## Failures, side by side\n\nEvery run at every requested tolerance, all families: *silently wrong* = "
        "claimed the tolerance (converged, or its own estimate ≤ tol) but missed it; *not converged* = said so "
        "within the cap; *over cap* = stopped by the cap.\n\n"
     << "| competitor | runs | silently wrong | not converged | over cap |\n|---|---|---|---|---|\n";
  std::map<std::string, Failures> pooled;
  for (const auto& f : families)
    for (const auto& [who, x] : f.failures) {
      Failures& p = pooled[who];
      p.runs += x.runs, p.silently_wrong += x.silently_wrong, p.not_converged += x.not_converged,
          p.over_cap += x.over_cap;
    }
  for (const auto& [who, p] : pooled)
    md << "| " << who << " | " << p.runs << " | " << p.silently_wrong << " (" << percent(p.silently_wrong, p.runs)
       << ") | " << p.not_converged << " (" << percent(p.not_converged, p.runs) << ") | " << p.over_cap << " ("
       << percent(p.over_cap, p.runs) << ") |\n";
}

/// A target per family: met when `value(f)` satisfies `meets`, listed with the numbers.
template <class Value, class Meets>
void family_target(std::ostringstream& md, const std::string& target, const std::vector<FamilyResult>& families,
                   Value value, Meets meets) {
  std::string met, missed;
  for (const auto& f : families) {
    const std::string item = f.name + " " + number(value(f));
    (meets(value(f)) ? met : missed) += item + ", ";
  }
  auto trim = [](std::string s) { return s.empty() ? std::string("none") : s.substr(0, s.size() - 2); };
  md << "- " << target << ": **met** for " << trim(met) << "; **missed** for " << trim(missed) << ".\n";
}

/// Our evaluations in this run, summed over every case and tolerance of a family: (runs, evaluations).
std::pair<long long, long long> evaluations_of(const FamilyResult& f, const std::string& who) {
  long long runs = 0, evaluations = 0;
  for (const Run& r : f.runs)
    if (r.competitor == who) ++runs, evaluations += r.evaluations;
  return {runs, evaluations};
}

/// The limit on our evaluations against the previous engine's, per family.
constexpr double kEvaluationGrowthLimit = 1.3;

/// this run / the baseline's evaluations of `who` on `f`; 0 when the baseline lacks the family or
/// its runs differ (a different case count).
double growth(const FamilyResult& f, const EvaluationBaseline& baseline, const std::string& who) {
  const auto family = baseline.totals.find(f.name);
  if (family == baseline.totals.end()) return 0.0;
  const auto before = family->second.find(who);
  const auto now = evaluations_of(f, who);
  if (before == family->second.end() || before->second.first != now.first || before->second.second <= 0) return 0.0;
  return double(now.second) / double(before->second.second);
}

void baseline_section(std::ostringstream& md, const std::vector<FamilyResult>& families,
                      const EvaluationBaseline& baseline) {
  md << "\n## Evaluations against the previous engine\n\nOur evaluations summed over every case and tolerance of "
        "a family, this run against the baseline ("
     << baseline.source << "): the same cases, the same counting. The limit is " << number(kEvaluationGrowthLimit)
     << "× for ours (the engine with the models' hints); without hints the first panels are each bisected once "
        "(integrate/cubature.h), shown for information.\n\n"
     << "| family | runs | ours | before | ratio | ours, no hints | before | ratio "
        "|\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& f : families) {
    const auto family = baseline.totals.find(f.name);
    auto before = [&](const std::string& who) {
      if (family == baseline.totals.end() || !family->second.count(who)) return std::string("—");
      return std::to_string(family->second.at(who).second);
    };
    md << "| " << f.name << " | " << evaluations_of(f, "ours").first << " | " << evaluations_of(f, "ours").second
       << " | " << before("ours") << " | " << number(growth(f, baseline, "ours")) << " | "
       << evaluations_of(f, "ours_no_hints").second << " | " << before("ours_no_hints") << " | "
       << number(growth(f, baseline, "ours_no_hints")) << " |\n";
  }
}

void targets_section(std::ostringstream& md, const std::vector<FamilyResult>& families,
                     const std::vector<BakeTiming>& bakes, const EvaluationBaseline* baseline) {
  auto ratio = [](const char* who) {
    return [who](const FamilyResult& f) {
      const auto it = f.evals_ratio.find(who);
      return it == f.evals_ratio.end() ? 0.0 : it->second;
    };
  };
  md << "\n## Targets, met or missed\n\n";
  family_target(md, "Within 2× of the oracle (ratio ≥ 0.5)", families, ratio("oracle"),
                [](double r) { return r >= 0.5; });
  family_target(md, "≥ 10× fewer evaluations than hcubature on the lune", families, ratio("hcubature_lune"),
                [](double r) { return r >= 10; });
  family_target(md, "≥ 1000× fewer than hcubature on the naive hemisphere (capped: lower bounds)", families,
                ratio("hcubature_naive"), [](double r) { return r >= 1000; });
  family_target(
      md, "Monte Carlo ≥ 10⁴× less accurate at equal time", families,
      [](const FamilyResult& f) { return f.mc_error_ratio_equal_time; }, [](double r) { return r >= 1e4; });
  int runs = 0, missed = 0;
  for (const auto& f : families) {
    const auto it = f.failures.find("ours");
    if (it == f.failures.end()) continue;
    runs += it->second.runs;
    missed += static_cast<int>(std::lround(f.missed_rate * it->second.runs));
  }
  const double met_fraction = runs ? 1.0 - double(missed) / runs : 0.0;
  md << "- ≥ 99.9% of our runs meet the requested tolerance: **" << (met_fraction >= 0.999 ? "met" : "missed") << "** ("
     << number(100 * met_fraction, 5) << "% of " << runs << " runs).\n";
  int dishonest = 0;
  for (const auto& f : families) {
    const auto it = f.failures.find("ours");
    if (it != f.failures.end()) dishonest += it->second.dishonest;
  }
  md << "- 0 dishonest runs of ours: **" << (dishonest == 0 ? "met" : "missed") << "** (" << dishonest << " of " << runs
     << ").\n";
  if (baseline)
    family_target(
        md, "Our evaluations ≤ " + number(kEvaluationGrowthLimit) + "× the previous engine's", families,
        [&](const FamilyResult& f) { return growth(f, *baseline, "ours"); },
        [](double r) { return r > 0.0 && r <= kEvaluationGrowthLimit; });
  const double limits[] = {5.0, 60.0};  // seconds on 2 threads: alpha = 8, alpha = 1000
  for (std::size_t k = 0; k < bakes.size() && k < 2; ++k) {
    const double median = util::median(bakes[k].seconds_2);
    md << "- Bake " << bakes[k].model << " g " << bakes[k].resolution[0] << "×" << bakes[k].resolution[1] << "×"
       << bakes[k].resolution[2] << " at 1e-9 on 2 threads ≤ " << number(limits[k]) << " s: **"
       << (median <= limits[k] ? "met" : "missed") << "** (median " << number(median) << " s).\n";
  }
}

/// A section that lists rows under a table header, or says there are none.
void listing(std::ostringstream& md, const std::string& heading, const std::string& intro, const std::string& header,
             const std::vector<std::string>& rows) {
  md << "\n## " << heading << "\n\n";
  if (rows.empty()) {
    md << "None in this run.\n";
    return;
  }
  md << intro << "\n\n" << header << "\n";
  for (const std::string& row : rows) md << row << "\n";
}

std::string triple(const Vec3Triple& v, int digits) {
  return number(v[0], digits) + "," + number(v[1], digits) + "," + number(v[2], digits);
}

void disagreements_section(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  std::vector<std::string> rows;
  for (const auto& f : families)
    for (const auto& d : f.disagreements)
      rows.push_back("| " + f.name + " | `" + d.model + "` | " + triple(d.i, 6) + " | " + triple(d.j, 6) + " | " +
                     number(d.boost_reference, 17) + " | " + number(d.ours_reference, 17) + " | " +
                     number(std::abs(d.boost_reference - d.ours_reference)) + " |");
  listing(md, "Cases where the references disagree", "Kept in every table above; verdicts allow for the difference.",
          "| family | model | i | j | Boost GK61 | ours at 1e-13 | difference |\n|---|---|---|---|---|---|---|", rows);
}

/// The competitors judged for missed / dishonest (each states an error estimate), in table order.
const std::vector<std::string> kJudged{"ours",           "ours_no_hints",   "hcubature_lune",
                                       "pcubature_lune", "hcubature_naive", "boost_gauss_kronrod",
                                       "boost_tanh_sinh"};

/// Our listed runs stay in the page when there are at most this many; more go in a collapsed block.
constexpr std::size_t kListedRunsInline = 30;

std::string eval_command(const Miss& m) {
  return "ganzfeld eval --model " + m.model + " --law g --i " + triple(m.i, 17) + " --j " + triple(m.j, 17) +
         " --tol " + number(m.tolerance);
}

void verdict_table(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  md << "Runs judged as in *Verdicts* above; a cell is *missed / dishonest* out of the family's runs of that "
        "competitor (every case at every tolerance). The oracle and Monte Carlo state no estimate and are not "
        "judged here.\n\n| family | runs each |";
  for (const auto& who : kJudged) md << " " << who << " |";
  md << "\n|---|---|";
  for (std::size_t k = 0; k < kJudged.size(); ++k) md << "---|";
  md << "\n";
  for (const auto& f : families) {
    const auto ours = f.failures.find("ours");
    md << "| " << f.name << " | " << (ours == f.failures.end() ? 0 : ours->second.runs) << " |";
    for (const auto& who : kJudged) {
      const auto it = f.failures.find(who);
      md << " "
         << (it == f.failures.end() ? std::string("—")
                                    : std::to_string(it->second.missed) + " / " + std::to_string(it->second.dishonest))
         << " |";
    }
    md << "\n";
  }
}

void worst_of_ours(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  md << "\nThe worst of our runs per family (largest error / (what it promised, min(tol, estimate), + resolution)), "
        "reproducible with the command shown:\n\n";
  bool any = false;
  for (const auto& f : families) {
    if (f.misses.empty()) continue;
    any = true;
    const Miss& m = *std::max_element(f.misses.begin(), f.misses.end(),
                                      [](const Miss& a, const Miss& b) { return a.excess() < b.excess(); });
    md << "- " << f.name << ": error " << number(m.achieved_error) << ", estimate " << number(m.estimate) << ", tol "
       << number(m.tolerance) << ", resolution " << number(m.resolution) << " (" << number(m.excess()) << "×): `"
       << eval_command(m) << "`\n";
  }
  if (!any) md << "- none: no run of ours missed or was dishonest in this run.\n";
}

void misses_section(std::ostringstream& md, const std::vector<FamilyResult>& families) {
  md << "\n## Missed tolerances and dishonest estimates, per family\n\n";
  verdict_table(md, families);
  worst_of_ours(md, families);
  std::vector<std::string> rows;
  for (const auto& f : families)
    for (const auto& m : f.misses)
      rows.push_back("| " + f.name + " | `" + m.model + "` | " + triple(m.i, 17) + " | " + triple(m.j, 17) + " | " +
                     number(m.tolerance) + " | " + number(m.achieved_error) + " | " + number(m.estimate) + " | " +
                     number(m.resolution) + " | " + std::to_string(m.evaluations) + " |");
  if (rows.empty()) return;
  const bool collapsed = rows.size() > kListedRunsInline;
  md << "\n"
     << (collapsed ? "<details><summary>All " + std::to_string(rows.size()) + " of our listed runs</summary>\n\n"
                   : std::string("All of our listed runs:\n\n"))
     << "| family | model | i | j | tol | achieved error | estimate | resolution | evaluations |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& row : rows) md << row << "\n";
  if (collapsed) md << "\n</details>\n";
}

void bake_section(std::ostringstream& md, const std::vector<BakeTiming>& bakes) {
  if (bakes.empty()) return;
  const unsigned cores = std::thread::hardware_concurrency();
  md << "\n## Bake throughput\n\nMedian [min–max] of " << bakes.front().seconds_1.size()
     << " runs each; a speed-up above the " << cores << " hardware threads would be suspect and is flagged.\n\n"
     << "| model | g nodes | 1 thread | 2 threads | speed-up (medians) | unconverged |\n|---|---|---|---|---|---|\n";
  for (const auto& b : bakes) {
    const double speedup = util::median(b.seconds_1) / util::median(b.seconds_2);
    md << "| " << b.model << " | " << b.resolution[0] << "×" << b.resolution[1] << "×" << b.resolution[2] << " | "
       << spread(b.seconds_1) << " | " << spread(b.seconds_2) << " | " << number(speedup)
       << (speedup > cores ? " (suspect: above the core count)" : "") << " | " << b.unconverged << " |\n";
  }
}

}  // namespace

EvaluationBaseline read_evaluation_baseline(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read the evaluation baseline '" + path + "'");
  EvaluationBaseline out;
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      out.source += (out.source.empty() ? "" : " ") + line.substr(line.find_first_not_of("# "));
      continue;
    }
    if (!header) {  // family,competitor,runs,evaluations
      header = true;
      continue;
    }
    std::istringstream fields(line);
    std::string family, competitor, runs, evaluations;
    if (!std::getline(fields, family, ',') || !std::getline(fields, competitor, ',') ||
        !std::getline(fields, runs, ',') || !std::getline(fields, evaluations))
      throw InputError("evaluation baseline '" + path + "': line '" + line +
                       "' is not family,competitor,runs,evaluations");
    try {
      out.totals[family][competitor] = {std::stoll(runs), std::stoll(evaluations)};
    } catch (const std::exception&) {
      throw InputError("evaluation baseline '" + path + "': line '" + line +
                       "' has no whole numbers of runs and evaluations");
    }
  }
  return out;
}

std::string performance_markdown(const std::vector<FamilyResult>& families, const CubatureBenchOptions& options,
                                 const std::vector<BakeTiming>& bakes, const std::string& command,
                                 const std::string& plot_file, const EvaluationBaseline* baseline) {
  std::ostringstream md;
  md << "<!-- Generated by `" << command << "`; do not edit by hand. -->\n"
     << "# Cubature performance against the peers\n\n";
  method_section(md, options, command);
  ratio_table(md, families);
  if (!plot_file.empty())
    md << "\n![work-precision](" << plot_file
       << ")\n\nIn the plot, an error below its case's resolution is drawn at the resolution (a geometric mean "
          "cannot take an exact 0).\n";
  failure_table(md, families);
  if (baseline) baseline_section(md, families, *baseline);
  targets_section(md, families, bakes, baseline);
  disagreements_section(md, families);
  misses_section(md, families);
  bake_section(md, bakes);
  return md.str();
}

void write_work_precision_plot(const std::vector<FamilyResult>& families, const std::string& path) {
  using namespace plot;
  const auto curves = work_precision(families);
  std::vector<double> xs, ys;
  for (const auto& [who, pts] : curves)
    for (auto [x, y] : pts) xs.push_back(x), ys.push_back(y);
  Canvas cv(1000, 720);
  cv.text(160, 16, "WORK-PRECISION: LAW OF VIGNETTING, ALL FAMILIES (GEOMETRIC MEANS)", kBlack);
  const Panel p{160, 60, 700, 620};
  const LogAxis ax = LogAxis::of(xs), ay = LogAxis::of(ys);
  draw_log_axes(cv, p, ax, ay, "evaluations", "achieved error");
  auto px = [&](double v) { return p.x0 + static_cast<int>(std::lround(ax.t(v) * (p.x1 - p.x0))); };
  auto py = [&](double v) { return p.y1 - static_cast<int>(std::lround(ay.t(v) * (p.y1 - p.y0))); };
  int series = 0, legend_y = 80;
  for (const auto& who : kCompetitors) {
    const auto it = curves.find(who);
    if (it == curves.end()) continue;
    const Rgb c = kPalette[series % 8];
    for (std::size_t k = 1; k < it->second.size(); ++k)
      cv.line(px(it->second[k - 1].first), py(it->second[k - 1].second), px(it->second[k].first),
              py(it->second[k].second), c, 2);
    for (auto [x, y] : it->second) cv.marker(px(x), py(y), series, c);
    cv.marker(735, legend_y + 6, series, c);
    cv.text(752, legend_y, who, kBlack);
    legend_y += 26;
    ++series;
  }
  cv.text(735, legend_y + 10, "POINTS: REQUESTED TOL", kGrey);
  cv.text(735, legend_y + 30, "LOOSE (LEFT) TO TIGHT", kGrey);
  write_png(cv, path);
}

}  // namespace ganzfeld::bench
