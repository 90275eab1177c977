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

#include "models/glsl.h"
#include "models/mass_hints.h"

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
  virtual void f_batch(std::span<const Vec3> i, std::span<const Vec3> j, std::span<double> out) const noexcept;

  /// Where the integrand k -> (k·n) f(k, fixed) [or f(fixed, k)] has its mass, built by HintBuilder
  /// (models/mass_hints.h); none by default.
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

  /// f as GLSL (models/glsl.h): the body of float f(vec3 i, vec3 j) in the local frame, written
  /// beside f in the model's own file. Nothing for a model with no closed form to emit (measured
  /// data, tables read from a file); the viewer then asks the service for f (docs/serve.md).
  virtual std::optional<GlslF> glsl_f() const { return std::nullopt; }

  /// The reflectance rho(cos theta) of a mirror (Dirac) term the model has besides f: the
  /// fraction of the flux from k reflected coherently into mirror(k), which no BRDF value can
  /// hold. f, and every law integrated from f (g, h, a, r, the tables), exclude it; renders add
  /// its exact contribution under extended sources: rho(j·n) to h, and to g when mirror(j) lies
  /// in the sky (rasterizer/shading.h). 0 for every model without one (all but he-torrance).
  virtual double mirror_reflectance(double /*cos_theta*/) const noexcept { return 0.0; }
  /// mirror_reflectance as GLSL (models/glsl.h): the body of float rho(float c), c = cos theta,
  /// written beside it; nothing for a model without a mirror term. The viewer adds it to its sky
  /// and Ganzfeld spheres as render does (serve/viewer/viewer.js).
  virtual std::optional<GlslF> glsl_mirror_reflectance() const { return std::nullopt; }
};

/// The sample of a direction i drawn for j (not necessarily of unit length): nothing where i lies
/// on or below the horizon or where model.pdf_incident(j, i), taken at i as drawn, is 0; else i
/// made unit with that density.
std::optional<IncidentSample> drawn_sample(const Model& model, const Vec3& j, const Vec3& i);

/// Whether the model has a mirror delta (Model::mirror_reflectance > 0) at some incidence: the
/// cosines k/64, k = 1..64, are tried.
bool has_mirror_delta(const Model& model) noexcept;

/// Cosine-weighted direction about n = +z from two uniform numbers (Malley's method: a uniform
/// point of the unit disk lifted to the hemisphere); density (i·n)/π.
Vec3 sample_cosine(double u1, double u2) noexcept;

using ModelPtr = std::shared_ptr<const Model>;

/// Mirror direction of v about n = +z: K&P's k = 2(i·n)n - i.
inline Vec3 mirror(const Vec3& v) { return {-v.x, -v.y, v.z}; }

}  // namespace ganzfeld
