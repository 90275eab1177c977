// The laws g, h, a by a reference that is not ganzfeld's engine: Boost.Math's
// adaptive gauss_kronrod<61>, nested (an outer integral over t of inner integrals over psi), on
// the lune written out here from its definition, with panels cut at the directions where the
// model's lobes peak. It shares with integrate/ only the definition of the domain:
//   g(i, j) = ∫_{k·n>0, k·i>0} (k·n) f(k, j) dk,  h(j) = g(n, j),  a(i) = ∫_{k·n>0} (k·n) f(i, k) dk.
// A second, differently built quadrature (gauss_kronrod<31>, the nesting swapped: psi outer)
// serves to tell a doubtful reference from a wrong engine (reports/extremes.h); a third, Boost's
// tanh_sinh nested at both levels, resolves layers at the horizon and the lune's tips (views and
// skies within 1e-6 of grazing) that bisection does not reach within its depth; and tanh_sinh in
// polar coordinates about the antipode of the fixed direction (AntipodeCoordinates) resolves the
// point where a microfacet model's integrand grows as 1/|k + fixed|, which the lune's lines cross.
#pragma once

#include <functional>
#include <vector>

#include "models/model.h"

namespace ganzfeld::reference {

/// A reference value and its error: `error` is Boost's estimate for the outer integral, and
/// `inner_error` bounds what the inner integrals' estimates add to it (their largest estimate
/// times the span of the outer variable).
struct Value {
  double value = 0.0;
  double error = 0.0;
  double inner_error = 0.0;
  long long evaluations = 0;
  /// false when the evaluation budget ran out (value 0, error infinite)
  bool resolved = true;
  double total_error() const { return error + inner_error; }
};

struct Options {
  double tolerance = 1e-10;  ///< Boost's relative termination tolerance, both levels
  /// An absolute error the whole integral may have (0: none), half for the outer integral and half
  /// for the inner ones: a caller that needs 1e-9 does not make a value of 3e-4 cost 1e-10 of itself
  /// across a kink, nor a value of 0.5 cost 5e-11.
  double absolute_tolerance = 0.0;
  unsigned max_depth = 10;  ///< Boost's bisection depth per panel, both levels
  /// Evaluations of f before the reference gives up (Value::resolved = false): a nested rule
  /// multiplies its levels' costs, and a lobe it cannot resolve would take hours.
  long long max_evaluations = 1'000'000'000'000;
  /// Break points: the mirror direction and the fixed direction (where K&P's specular and
  /// backscatter lobes peak) and, when set, the peaks, widths and horizon layer of the model's
  /// mass hints (models/mass_hints.h: the model's own data, not the engine's).
  bool use_mass_hints = true;
  bool swapped = false;  ///< psi outer, t inner, gauss_kronrod<31>: the second reference
  /// Boost's tanh_sinh at both levels (t outer) instead of gauss_kronrod: its double-exponential
  /// nodes crowd towards every panel's ends, where a layer 1e-9 thick at the horizon (a view
  /// 1e-9 above it) or the lune's tip takes a bisecting rule ~30 levels. Ignores max_depth.
  bool tanh_sinh = false;
  /// Polar coordinates about the antipode of the fixed direction (AntipodeCoordinates) instead of
  /// the lune's, tanh_sinh at both levels: the fourth reference (ignores swapped and tanh_sinh).
  bool about_antipode = false;
  /// The tolerance relative to each integral's L1 norm over all its panels (false: relative to
  /// each panel's own integral, as Boost does and as tests/independent_reference_test.cpp pins it).
  bool global_tolerance = true;
};

/// The lune {k·n > 0, k·pole > 0} (pole = n: the hemisphere) in coordinates about its edge axis
/// e = n × pole / |n × pole|: k = cos t (cos psi n + sin psi b) + sin t e, b = e × n,
/// t ∈ (-pi/2, pi/2), psi ∈ (theta_pole - pi/2, pi/2), dk = cos t dt dpsi; k·n = cos t cos psi.
struct LuneCoordinates {
  Vec3 n{0, 0, 1}, e, b;
  double psi_lo = 0.0, psi_hi = 0.0;
  bool empty = false;  ///< pole at the nadir
  /// `hemisphere_edge`: e when pole = n (any horizontal unit vector).
  LuneCoordinates(const Vec3& pole, const Vec3& hemisphere_edge);
  Vec3 direction(double t, double psi) const;
  /// (t, psi) of a direction, for break points.
  std::pair<double, double> coordinates(const Vec3& k) const;
};

/// The domain {k·n > 0, k·pole > 0} in polar coordinates about p = -fixed, the antipode of the
/// direction the law holds fixed: k = cos r p + sin r (cos beta u + sin beta v), r ∈ [0, pi],
/// dk = sin r dr dbeta. A microfacet model's half vector (k + fixed)/|k + fixed| turns once about
/// its lobe while k circles p, so near p its integrand (k·n) f(k, fixed) grows as D/|k + fixed|
/// (dk = 4 (fixed·h) dh, Walter et al. 2007): a point singularity 1e-9 below the horizon when fixed is
/// 1e-9 above it, which the lune's coordinates meet across a panel and these take in r's Jacobian.
struct AntipodeCoordinates {
  Vec3 n{0, 0, 1}, pole, p, u, v;
  bool empty = false;  ///< pole at the nadir
  AntipodeCoordinates(const Vec3& pole, const Vec3& fixed);
  Vec3 direction(double r, double beta) const;
  /// The interval of r on the ray at beta inside the domain (lo >= hi: none).
  std::pair<double, double> radii(double beta) const;
  /// beta of a direction (0 for ±p).
  double beta(const Vec3& k) const;
};

/// Panels of [lo, hi] cut at each centre strictly inside and at ±0.05, ±0.2 around it; cuts
/// closer than 1e-9 are merged (a sliver panel makes a relative-error rule recurse on noise).
std::vector<double> cuts(double lo, double hi, const std::vector<double>& centres);

/// ∫_lune (k·n) f(k) dk = ∫∫ cos t (k·n) f(k) dt dpsi over the cut panels.
Value lune_integral(const std::function<double(const Vec3&)>& f, const LuneCoordinates& lune,
                    const std::vector<double>& t_cuts, const std::vector<double>& psi_cuts, const Options& options);

/// The laws of the model (integrate/laws.h defines them; this computes them apart).
Value vignetting(const Model& model, const Vec3& i, const Vec3& j, const Options& options = {});
Value darkening(const Model& model, const Vec3& j, const Options& options = {});
Value albedo(const Model& model, const Vec3& i, const Options& options = {});

}  // namespace ganzfeld::reference
