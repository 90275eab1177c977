// Beard–Maxwell: Maxwell, Beard, Weiner, Ladd & Ladd, "Bidirectional Reflectance Model Validation
// and Utilization", AFAL TR-73-303 (ERIM, 1973), in the form of the NEF database (Nonconventional
// Exploitation Factors Data System, ORD TR 257-96, 1996) as Westlund & Meyer give it ("A BRDF
// database employing the Beard-Maxwell reflection model", Graphics Interface 2002); Walker 1999
// (MSc thesis, U. Oregon), ch. III "Beard-Maxwell", eq. III.33. A paint: a first surface
// (resin/air interface, a facet model) over a pigmented volume.
//
//   f = [R(beta)/R(0)] rho_fs(theta_N) cos^2 theta_N / (cos theta_i cos theta_r) SO(theta_N, beta)
//       + rho_D + 2 rho_V / (cos theta_i + cos theta_r)
//
//   h = (i + j)/|i + j| the facet normal, theta_N its angle from n; beta the angle of incidence on
//       that facet, half the angle between i and j (cos beta = i.h = |i + j|/2);
//   R  the unpolarized Fresnel reflectance for the complex index n + ik (fresnel_complex);
//   SO = (1 + (theta_N/Omega) e^{-2 beta/tau}) / (1 + theta_N/Omega)   shadowing/obscuration,
//        tau and Omega fitted angles (SCATMECH, NIST: Maxwell_Beard_Shadow_Function);
//   rho_fs(theta_N) the first-surface BRDF at the monostatic geometry i = j (there beta = 0, so
//       the Fresnel ratio, SO and cos^2 theta_N/(cos theta_i cos theta_r) are all 1 and f - rho_D -
//       rho_V/cos = rho_fs): a measured table in the original, a two-parameter fit in the NEF;
//   rho_D  a Lambertian BRDF value (1/sr), rho_V the volumetric (Lommel–Seeliger-like) term (1/sr).
//
// The first surface here is either ganzfeld's stand-in (the NEF fit's form is not available to
// us; docs/models.md) — the Beckmann facet distribution written as a monostatic BRDF,
//   rho_fs(theta_N) = B D(theta_N) / (4 cos^2 theta_N),  D = exp(-tan^2 theta_N/m^2)/(pi m^2 cos^4 theta_N)
// (∫ D cos theta_N d omega_h = 1), so that the first-surface term is B [R(beta)/R(0)] D SO /
// (4 cos theta_i cos theta_r): a microfacet BRDF with Beard–Maxwell's SO for the shadowing and B
// its reflectance at normal incidence (B = R(0) for a physical interface) — or the user's table of
// rho_fs(theta_N) (`file=PATH`, format below).
//
// Differences from the thesis's eq. III.33 (docs/models.md): SO is printed upside down and without
// 1/Omega in the numerator, (1 + theta_N)/(1 + (theta_N/Omega) e^{-alpha/tau}) (>= 1: not a
// shadowing factor); rho_D is printed rho_d/pi; the volumetric term carries Hapke's S(alpha) R_f(alpha, g)
// (the Oregon library's variant, not in the NEF form).
//
// Horizon: the printed cos theta_i cos theta_r and cos theta_i + cos theta_r in the denominators
// are floored at kGrazingCosFloor (models/classic_models.h), as for Phong, Ward and Hapke.
#pragma once

#include <string>
#include <vector>

#include "models/model.h"
#include "models/registry.h"

namespace ganzfeld {

/// SO(theta_N, beta) = (1 + (theta_N/Omega) e^{-2 beta/tau}) / (1 + theta_N/Omega), all four
/// angles in the same unit (radians here). 1 at beta = 0 and at theta_N = 0; in (0, 1].
double beard_maxwell_so(double theta_N, double beta, double tau, double omega) noexcept;

/// A user's first-surface table (docs/models.md, "first-surface table"):
///   ganzfeld-beard-maxwell-first-surface 1
///   theta_N: 0 2 5 10 ...     degrees, strictly increasing, in [0, 90]
///   rho_fs: v0 v1 v2 ...      1/sr, in [0, 1e6], one per theta_N
/// interpolated by monotone piecewise-cubic Hermite in theta_N (Fritsch & Carlson 1980, SIAM J.
/// Numer. Anal. 17(2); the end slopes as in SciPy's PchipInterpolator), with slope 0 at a node at
/// theta_N = 0 (rho_fs is even in theta_N), held at the end values outside the grid. C^1, so
/// the cubature is not slowed by a kink at every node (linear interpolation cost 50x more
/// evaluations); monotone, so never negative and no overshoot.
struct FirstSurfaceTable {
  std::vector<double> theta_N;  ///< degrees
  std::vector<double> rho_fs;   ///< 1/sr
};
/// Parses the text; throws InputError naming the file, the line and the problem.
FirstSurfaceTable parse_first_surface_table(const std::string& text, const std::string& name);

/// rho_fs(theta_N): the built-in Beckmann stand-in or a user table.
class FirstSurface {
 public:
  /// B D(theta_N)/(4 cos^2 theta_N) with the Beckmann D of RMS slope m.
  static FirstSurface beckmann(double B, double m);
  /// `digest`: util::content_digest of the table file's bytes.
  static FirstSurface table(std::string path, FirstSurfaceTable table, std::string digest);

  /// rho_fs(theta_N) cos^2 theta_N (1/sr), for theta_N in radians with its cosine; 0 for
  /// cos_N <= 0. (The product is what the BRDF needs, and is finite for the Beckmann form.)
  double rho_fs_cos2(double theta_N, double cos_N) const noexcept;
  /// Angular half width (radians, in theta_N) over which rho_fs cos^2 falls by 1/e from theta_N = 0,
  /// for mass hints: a table's, between its nodes (pi/2 when it never does); the Beckmann lobe's
  /// atan m (the 1/e width of exp(-tan^2/m^2); its 1/cos^4 makes the true one ~2% wider).
  double width() const noexcept { return width_; }

  bool is_table() const { return !path_.empty(); }
  const std::string& path() const { return path_; }
  const std::string& digest() const { return digest_; }  ///< "" for the built-in lobe
  double B() const { return B_; }
  double m() const { return m_; }

 private:
  FirstSurface() = default;
  double B_ = 0.0, m_ = 1.0;
  std::string path_, digest_;
  FirstSurfaceTable table_;     // theta_N converted to radians
  std::vector<double> slopes_;  // d rho_fs/d theta_N at the nodes (monotone Hermite)
  double width_ = 0.0;
};

class BeardMaxwell final : public Model {
 public:
  /// tau and omega in degrees (as NEF/DIRSIG fit files give them); rho_D, rho_V in 1/sr.
  BeardMaxwell(double n, double k, FirstSurface first_surface, double tau_deg, double omega_deg, double rho_D,
               double rho_V);

  std::string spec() const override;
  std::string content_digest() const override { return fs_.digest(); }
  /// Isotropic; reciprocal (every factor is symmetric in i, j: measured bit-exact); not
  /// plausible: the first-surface term has no shadowing that vanishes at the horizon, so its
  /// albedo grows like 1/cos theta_i at grazing incidence (and rho_D, rho_V are unbounded fits).
  Traits traits() const override { return {true, true, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  /// A peak at mirror(fixed) (the first-surface lobe, width sqrt(2) x its theta_N width), one at
  /// `fixed` (SO's conical kink at beta = 0, width tau), and a horizon layer mu_fixed when
  /// rho_V > 0 and mu_fixed < 0.3 (the 1/(mu + mu_fixed) switch).
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;

  /// The first-surface term alone (1/sr).
  double first_surface(const Vec3& i, const Vec3& j) const noexcept;
  /// rho_D + 2 rho_V/(mu_i + mu_j) (1/sr).
  double volumetric(const Vec3& i, const Vec3& j) const noexcept;
  /// R(beta)/R(0) for cos beta.
  double fresnel_ratio(double cos_beta) const noexcept;

 private:
  double n_, k_;
  FirstSurface fs_;
  double tau_deg_, omega_deg_, tau_, omega_;  // tau_, omega_ in radians
  double rho_D_, rho_V_;
  double R0_;
};

/// R(0) below which the Fresnel ratio R(beta)/R(0) is refused (n near 1 with k near 0).
inline constexpr double kBeardMaxwellMinR0 = 1e-6;

void register_beard_maxwell_models(std::vector<ModelInfo>& catalogue);

}  // namespace ganzfeld
