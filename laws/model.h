// The one interface every BRDF model implements (Koenderink–Pont lobes, halfway-vector-disk
// models, the classic catalogue, measured tables).
//
// Conventions (K&P, "Material Properties and Extended Sources for Surface Rendering"):
// local frame with the normal n = +z; i points towards the source, j towards the eye; both are
// unit vectors. f(i, j) is the BRDF ("law of shading") in 1/sr.
#pragma once

#include <memory>
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
/// hoping its first nodes land on a lobe (design.md, integrate/).
struct Peak {
  Vec3 direction;  ///< unit vector of the lobe's maximum (may lie outside the domain)
  double width;    ///< angular scale in radians (e.g. sqrt(2/alpha) for a cosine-power lobe)
};
struct MassHints {
  std::vector<Peak> peaks;
  /// Thickness in k·n of a layer of mass hugging the horizon (asperity lobes, the
  /// 1/((i+j)·n) factor of perfect backscatter); 0 when there is none.
  double horizon_layer = 0.0;
};

/// Which argument of f an integral runs over while the other is held fixed.
enum class Varying {
  incident,  ///< k in f(k, j): laws of vignetting g and darkening h
  outgoing,  ///< k in f(i, k): albedo a
};

class Model {
 public:
  virtual ~Model() = default;

  /// Canonical spec string (all parameters, normalized weights): the material's identity.
  virtual std::string spec() const = 0;
  virtual Traits traits() const = 0;

  /// The BRDF for unit i, j in the local frame. 0 when either is strictly below the horizon;
  /// on the horizon the formula's limit. Never NaN or Inf.
  virtual double f(const Vec3& i, const Vec3& j) const noexcept = 0;

  /// f over arrays (the integrator calls this for whole panels). out[m] = f(i[m], j[m]).
  virtual void f_batch(std::span<const Vec3> i, std::span<const Vec3> j,
                       std::span<double> out) const noexcept;

  /// Where the integrand k -> (k·n) f(k, fixed) [or f(fixed, k)] has its mass.
  virtual MassHints mass_hints(const Vec3& fixed, Varying varying) const;
};

using ModelPtr = std::shared_ptr<const Model>;

/// Mirror direction of v about n = +z: K&P's k = 2(i·n)n - i.
inline Vec3 mirror(const Vec3& v) { return {-v.x, -v.y, v.z}; }

}  // namespace ganzfeld
