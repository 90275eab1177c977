// The halfway-vector-disk (HVD) BRDFs of Edwards, Boulos, Johnson, Shirley, Ashikhmin, Stark and
// Wyman, "The Halfway Vector Disk for BRDF Modeling" (ACM TOG 2006).
//
// For a fixed outgoing direction ω_o (our j, towards the eye), every unnormalized halfway vector
// H = ω_i + ω_o lies on the unit hemisphere translated to the tip of ω_o; its base is a unit disk
// in the plane z = ω_o·N, centred at ω_o's tangential part ω_uv. A PDF p on that disk defines a
// BRDF whose cosine-weighted integral over *incident* directions is exactly ∫_disk p dA
// (eq. 4–11): 1 when p is a PDF supported inside the disk. Two maps of H to the disk:
//   scaling projection    (eq. 15): h = (ω_o·N)/(H·N) H;  ρ = p(h)(ω_o·N)² / (4(ω_i·N)(ω_i·Ĥ)(Ĥ·N)³)  (eq. 20)
//   orthogonal projection (eq. 22): h = H − (ω_i·N)N;    ρ = p(h)|H|² / (4(ω_i·Ĥ)²) = p(h)           (eq. 24)
// (|H|² = 4(ω_i·Ĥ)², so eq. 24 is just ρ = p(h): ρ (ω_i·N) dω_i = p dA.)
// The models integrate to 1 over ω_i for every ω_o, not over ω_o: they are not reciprocal, and
// their albedo a differs from their law of darkening h (checked by `ganzfeld verify`).
//
// Tangent frame: u = +x, v = +y of the local frame (n = +z); anisotropic radii refer to it.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "models/model.h"

namespace ganzfeld {

namespace hvd {

/// A point of the (u, v) plane.
struct Uv {
  double u = 0.0, v = 0.0;
};

/// The elliptical lump of eq. 27 (eq. 26 when R_u = R_v): a unit-volume PDF on the plane,
/// (n+1)/(π R_u R_v) [1 − (u−c_u)²/R_u² − (v−c_v)²/R_v²]^n inside the ellipse, 0 outside.
struct Lump {
  Uv centre;
  double R_u = 1.0, R_v = 1.0, n = 0.0;
  double pdf(const Uv& h) const noexcept;
  /// A point drawn with density pdf from two uniform numbers: eq. 28 on the unit lump,
  /// r = sqrt(1 − ξ1^(1/(n+1))), θ = 2π ξ2, then scaled by R_u, R_v and moved to the centre
  /// (eq. 29 and the text after it).
  Uv sample(double xi1, double xi2) const noexcept;
};

/// Schlick's Fresnel approximation, eq. 30 / eq. 34: F_0 + (F_90 − F_0)(1 − cos θ)^5.
double schlick(double cos_theta, double F_0, double F_90 = 1.0) noexcept;
/// F_0 of a dielectric of relative index η, eq. 31: ((η − 1)/(η + 1))².
double f0_from_eta(double eta) noexcept;

/// Largest radius of a lump centred at the origin that stays inside the disk (eq. 32 text):
/// 1 − sin θ_o, evaluated as cos²θ_o / (1 + sin θ_o) (no cancellation at grazing).
double max_specular_radius(double cos_theta_o) noexcept;

/// Scaling projection of H = i + j onto the disk (eq. 15), (u, v) part. Requires (i + j)·n > 0.
Uv scaling_uv(const Vec3& i, const Vec3& j) noexcept;
/// Orthogonal projection (eq. 22), (u, v) part: i_uv + j_uv.
Uv orthogonal_uv(const Vec3& i, const Vec3& j) noexcept;

/// Inverse of scaling_uv for outgoing j (eq. 21 then eq. 13): the disk point (u, v) lies at height
/// j·n, Ĥ = (u, v, j·n)/|·| and i = 2(j·Ĥ)Ĥ − j. Nothing unless i·n > 0 (points off the disk).
std::optional<Vec3> incident_from_scaling(const Uv& h, const Vec3& j) noexcept;
/// Inverse of orthogonal_uv for outgoing j (eq. 25): the disk point is i_uv + j_uv, so i_uv =
/// h − j_uv and the i·n that eq. 25 needs is recovered as sqrt(1 − |i_uv|²). Nothing for points
/// off the disk (|h − j_uv| >= 1).
std::optional<Vec3> incident_from_orthogonal(const Uv& h, const Vec3& j) noexcept;

/// dμ(h)/dω_i for the scaling projection: Q(ω_i) = p(h) · this, with Q = ρ (ω_i·N) the
/// incident-direction PDF (eq. 8 and 19): (ω_o·N)² |H|² / (2 (H·N)³). 0 when (i+j)·n <= 0.
double scaling_jacobian(const Vec3& i, const Vec3& j) noexcept;

}  // namespace hvd

/// hvd-empirical, eq. 32–33: Lambert weighted by 1 − F(θ_o) plus F(θ_o) times a specular lump at
/// the origin and a retro-reflective lump at the disk centre, scaling projection. Radii are
/// given as fractions of their largest energy-conserving values: R_s = rs (1 − sin θ_o),
/// R_r = rr (per axis: rsu, rsv, rru, rrv).
class HvdEmpirical final : public Model {
 public:
  struct Params {
    double C_d = 0.5, F_0 = 0.04, eta = 0.0, k = 0.0, n_s = 100.0, n_r = 10.0;
    double rs_u = 1.0, rs_v = 1.0, rr_u = 1.0, rr_v = 1.0;
  };
  explicit HvdEmpirical(const Params& p) : p_(p) {}
  std::string spec() const override;
  Traits traits() const override;
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// Eq. 12–13, 21, 28–29: the diffuse part by cosine, the lumps on the disk, chosen in
  /// proportion to their shares of ∫ f (i·n) di, so that f (i·n)/pdf = (1 − F) C_d + F for every
  /// draw: perfect importance sampling of the law of darkening.
  std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override;
  double pdf_incident(const Vec3& j, const Vec3& i) const override;
  const Params& params() const { return p_; }
  /// The disk PDF of eq. 32 for outgoing direction j (lumps placed and sized for j).
  std::array<hvd::Lump, 2> lumps(const Vec3& j) const noexcept;

 private:
  Params p_;
};

/// hvd-fit, eq. 34–36: Lambert weighted by 1 − F_fit(θ_o) plus F_fit(θ_o) times two lumps at the
/// origin, orthogonal projection. Radii are absolute and not constrained: where a lump leaves
/// the disk the model loses F_fit × (the lump's volume outside the disk).
class HvdFit final : public Model {
 public:
  struct Params {
    double C_d = 0.5, F_0 = 0.04, F_90 = 1.0, k = 0.0, n_1 = 100.0, R_1 = 0.2, n_2 = 10.0, R_2 = 0.5;
  };
  explicit HvdFit(const Params& p) : p_(p) {}
  std::string spec() const override;
  Traits traits() const override;
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  std::optional<GlslF> glsl_f() const override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// Eq. 25, 28–29 with the orthogonal projection; draws whose lump point falls off the disk
  /// fail (that is the energy the model loses), so the density integrates to the success rate.
  std::optional<IncidentSample> sample_incident(const Vec3& j, const std::array<double, 3>& u) const override;
  double pdf_incident(const Vec3& j, const Vec3& i) const override;
  const Params& params() const { return p_; }
  std::array<hvd::Lump, 2> lumps() const noexcept;

 private:
  Params p_;
};

}  // namespace ganzfeld
