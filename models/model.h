// The one interface every BRDF model implements (Koenderink–Pont lobes, halfway-vector-disk
// models, the classic catalogue, measured tables).
//
// Conventions (K&P, "Material Properties and Extended Sources for Surface Rendering"):
// local frame with the normal n = +z; i points towards the source, j towards the eye; both are
// unit vectors. f(i, j) is the BRDF ("law of shading") in 1/sr.
#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace ganzfeld {

using Vec3 = glm::dvec3;

/// Energy classes of K&P's section "General Properties of BRDFs".
enum class EnergyClass {
  conserving,     ///< unit albedo for every incidence (only Lambert among the K&P lobes)
  plausible,      ///< non-negative, reciprocal, albedo <= 1
  not_plausible,  ///< violates one of K&P's constraints (1)-(3)
};

const char* to_string(EnergyClass c);

struct Traits {
  bool isotropic = true;   ///< invariant under rotation about n: laws depend on (i·n, j·n, i·j)
  bool reciprocal = true;  ///< f(i,j) = f(j,i) (Helmholtz), hence a = h
  EnergyClass energy = EnergyClass::plausible;
};

/// Where a model's integrand has its mass, so the integrator splits panels there instead of
/// hoping its first nodes land on a lobe (integrate/cubature.h).
struct Peak {
  Vec3 direction;  ///< unit vector of the lobe's maximum (may lie outside the domain)
  double width;    ///< angular scale in radians (e.g. sqrt(2/alpha) for a cosine-power lobe)
  /// Angular scale across the plane of n and the peak, when the lobe is elongated (0: the same
  /// as width). Halfway-vector lobes near grazing are 10^4 times thinner across than along.
  double across = 0.0;
};
struct MassHints {
  std::vector<Peak> peaks;
  /// Thickness in k·n of a layer of mass hugging the horizon (asperity lobes, the
  /// 1/((i+j)·n) factor of perfect backscatter); 0 when there is none.
  double horizon_layer = 0.0;
  /// Declares one more layer: of several, the thinnest is the one the grid must resolve.
  void add_horizon_layer(double thickness) {
    if (thickness > 0.0) horizon_layer = horizon_layer > 0.0 ? std::min(horizon_layer, thickness) : thickness;
  }
  /// The integrand behaves like (k·n)^nu at the horizon with a non-integer nu < 2 (Minnaert's
  /// (k·n)^(1+xi)): a weak singularity at the edge of the domain, which the integrator grades.
  bool rough_horizon = false;
  /// Half great circles from -crease_axis to +crease_axis across which the integrand jumps or
  /// kinks, given by their longitude about crease_axis: phi(k) = atan2(k·u, k·n) with
  /// u = crease_axis × n, in (-pi/2, pi/2). Poulin–Fournier's cylinder shadowing depends only on
  /// the angle of k projected on the plane perpendicular to the cylinders, so its jumps lie on
  /// such circles. The integrator then works in a frame whose meridians are these circles and
  /// cuts its panels there (integrate/laws_integrals.cpp): the jumps are resolved by splitting,
  /// not by bisecting towards them. crease_axis must be horizontal (·n = 0); zero means none.
  Vec3 crease_axis{0.0, 0.0, 0.0};
  std::vector<double> crease_longitudes{};
};

/// Which argument of f an integral runs over while the other is held fixed.
enum class Varying {
  incident,  ///< k in f(k, j): laws of vignetting g and darkening h
  outgoing,  ///< k in f(i, k): albedo a
};

/// An incident direction drawn for a fixed outgoing direction (Model::sample_incident).
struct IncidentSample {
  Vec3 i{0, 0, 1};   ///< unit, local frame, i·n > 0
  double pdf = 0.0;  ///< its density per steradian, = pdf_incident(j, i)
};

class Model {
 public:
  virtual ~Model() = default;

  /// Canonical spec string (all parameters, normalized weights): the material's identity.
  virtual std::string spec() const = 0;
  /// What the model's data files hold: util::content_digest of their bytes, "" for a model that
  /// its spec alone defines. A spec names a data file by its path, which says nothing about the
  /// bytes there now, so tables and the cache key measured models by this (tables/cache.h).
  virtual std::string content_digest() const { return {}; }
  virtual Traits traits() const = 0;

  /// The BRDF for unit i, j in the local frame. 0 when either is strictly below the horizon;
  /// on the horizon the formula's limit. Never NaN or Inf.
  virtual double f(const Vec3& i, const Vec3& j) const noexcept = 0;

  /// f over arrays (the integrator calls this for whole panels). out[m] = f(i[m], j[m]).
  virtual void f_batch(std::span<const Vec3> i, std::span<const Vec3> j,
                       std::span<double> out) const noexcept;

  /// Where the integrand k -> (k·n) f(k, fixed) [or f(fixed, k)] has its mass.
  virtual MassHints mass_hints(const Vec3& fixed, Varying varying) const;

  /// Importance sampling of the incident direction i for the outgoing (viewing) direction j,
  /// from three uniform numbers in [0, 1): what a path tracer needs, and an unbiased estimator
  /// of the law of darkening, h(j) = E[f(i, j)(i·n)/pdf]. Nothing when the draw falls outside
  /// the BRDF's support (mass a model loses, e.g. hvd-fit lumps hanging off the disk), or when
  /// j·n <= 0. The default draws i with density (i·n)/π (Malley's method).
  virtual std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const;
  /// The density per steradian with which sample_incident draws i (0 where it never does); its
  /// integral over the hemisphere is the probability that a draw succeeds.
  virtual double pdf_incident(const Vec3& j, const Vec3& i) const;
};

/// Cosine-weighted direction about n = +z from two uniform numbers (Malley's method: a uniform
/// point of the unit disk lifted to the hemisphere); density (i·n)/π.
Vec3 sample_cosine(double u1, double u2) noexcept;

using ModelPtr = std::shared_ptr<const Model>;

/// Mirror direction of v about n = +z: K&P's k = 2(i·n)n - i.
inline Vec3 mirror(const Vec3& v) { return {-v.x, -v.y, v.z}; }

}  // namespace ganzfeld
