#include "reports/plausibility.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

#include <tbb/parallel_for.h>

#include "integrate/laws.h"
#include "models/classic_models.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {

/// Blinn 1977 as he wrote it: the specular term is a *reflected intensity* added to the
/// Lambert-shaded one, I = I_L (kd (i·n) + ks C (h·n)^n), with no (i·n) on the specular part —
/// as a BRDF f = I/(I_L (i·n)) = kd/π + ks C (h·n)^n / (i·n). This is the form K&P's claim
/// ("Phong and Blinn-Phong violate reciprocity") is about; the catalogue's blinn-phong is the
/// symmetric BRDF form. Kept here, where the claim is measured.
class BlinnPhongIntensityForm final : public Model {
 public:
  BlinnPhongIntensityForm(double kd, double ks, double n) : kd_(kd), ks_(ks), n_(n), C_((n + 2.0) / (2.0 * pi)) {}
  std::string spec() const override {
    return "blinn-phong, intensity form (Blinn 1977): kd=" + format_number(kd_) + ",ks=" + format_number(ks_) +
           ",n=" + format_number(n_);
  }
  Traits traits() const override { return {true, false, EnergyClass::not_plausible}; }
  double f(const Vec3& i, const Vec3& j) const noexcept override {
    if (i.z < 0.0 || j.z < 0.0) return 0.0;
    const Vec3 s = i + j;
    const double len = glm::length(s);
    const double hn = len > 0.0 ? std::max(0.0, s.z / len) : 0.0;
    return kd_ / pi + ks_ * C_ * std::pow(hn, n_) / std::max(i.z, kGrazingCosFloor);
  }
  MassHints mass_hints(const Vec3& fixed, Varying) const override {
    return HintBuilder().lobe(mirror(fixed), std::min(1.0, 2.0 / std::sqrt(n_ + 1.0))).build();
  }

 private:
  double kd_, ks_, n_, C_;
};

constexpr const char* kIntensityForm = "blinn-phong-intensity-form";

ModelPtr make_case(const std::string& spec) {
  if (spec == kIntensityForm) return std::make_shared<BlinnPhongIntensityForm>(0.5, 0.5, 20.0);
  return parse_model(spec);
}

Vec3 dir(double theta_deg, double phi_deg) {
  const double t = theta_deg * pi / 180.0, p = phi_deg * pi / 180.0;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

std::string angles(double ti, double tj, double phi) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g, %g, %g", ti, tj, phi);
  return buffer;
}

const double kThetas[] = {0.0, 10.0, 30.0, 50.0, 70.0, 85.0, 89.0, 89.9};
const double kPhis[] = {0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 300.0};
const double kIncidences[] = {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0};

}  // namespace

bool PlausibilityRow::traits_consistent() const {
  if (declared.reciprocal != reciprocal()) return false;
  const bool claims_plausible = declared.energy != EnergyClass::not_plausible;
  if (claims_plausible && !(non_negative() && reciprocal() && conserves())) return false;
  if (declared.energy == EnergyClass::conserving && !ganzfeld_invisible()) return false;
  return true;
}

std::vector<PlausibilityCase> plausibility_cases() {
  std::vector<PlausibilityCase> cases{
      {"lambert", "white Lambert: the reference, invisible in a Ganzfeld"},
      {"minnaert:xi=0.3", "K&P bulk scattering, shallow"},
      {"minnaert:xi=2.7", "K&P bulk scattering, strong edge darkening"},
      {"specular:alpha=1000", "K&P specular lobe, sharpest tested"},
      {"backscatter:alpha=8", "K&P backscatter, sharp"},
      {"asperity:alpha=4", "K&P asperity (velvet)"},
      {"hvd-empirical:cd=1,f0=0.04,k=0,ns=100,nr=10", "white: energy conserved over incidence for every view"},
      {"hvd-empirical:cd=1,f0=0.5,k=0.4,ns=50,nr=10,rsu=1,rsv=0.2", "white, anisotropic lumps"},
      {"hvd-fit:cd=1,f0=0.2,f90=1,k=0.4,n1=20,r1=0.3,n2=5,r2=0.8", "white, lumps off the disk: loses energy"},
      {"phong:kd=0.2,ks=0.8,n=1", "original Phong, broad lobe"},
      {"phong-lewis:kd=0,ks=1,n=1", "Lewis's normalized Phong, all specular"},
      {"blinn-phong:kd=0,ks=1,n=1", "Blinn-Phong BRDF form, all specular"},
      {kIntensityForm, "Blinn's original intensity form (not in the catalogue): what K&P's claim is about"},
      {"cook-torrance:kd=0,ks=1,m=0.5", "rough metal-like facets, specular only"},
      {"ward:rho_d=0,rho_s=1,alpha=0.5", "Ward, all specular, wide lobe"},
      {"ward:rho_d=0,rho_s=1,alpha=0.05", "Ward, all specular, sharp lobe"},
      {"oren-nayar:sigma=0,rho=1", "sigma = 0: must be white Lambert"},
      {"oren-nayar:sigma=0.6,rho=1", "roughest allowed facets"},
      {"hapke:rho=1,g=0.6,phase=0", "white Lommel-Seeliger with opposition surge"},
      {"blinn-dusty:w=1,tau=1000,phase=4,g=0.9", "white thick dust, strong backscatter (Henyey-Greenstein)"},
      {"beard-maxwell:b=0,rho_d=0.3183098861837907,rho_v=0", "first surface off, rho_D = 1/pi: must be white Lambert"},
      {"beard-maxwell:b=0,rho_d=0,rho_v=0.07957747154594767",
       "volumetric term alone, rho_V = 1/(4 pi): albedo -> 1 at grazing"},
      {"beard-maxwell:n=0.2,k=3,b=0.9,m=0.4,tau=5,omega=10,rho_d=0,rho_v=0", "metallic first surface alone, rough"},
      {"poulin-fournier:kd=1,ks=0,d=2,h=0",
       "white Lambertian half-cylinders: masked light is lost (no interreflection)"},
      {"poulin-fournier:kd=0,ks=1,n=1,d=1.5,h=0", "overlapping cylinders, all specular, broad lobe"},
      {"ggx:alpha=0.01", "sharp GGX, F = 1: single scattering loses energy only at grazing"},
      {"ggx:alpha_x=0.05,alpha_y=0.5,g2=separable", "anisotropic GGX, separable G2"},
      {"charlie:alpha=0.05", "sharp sheen: the visibility term lets the albedo exceed 1 at grazing"},
      {"ashikhmin-shirley:rd=1,rs=0,nu=10000,nv=10000", "white substrate under a sharp clear coat"},
      {"ashikhmin-shirley:rd=1,rs=1,nu=10000,nv=10000", "all specular (F = 1), sharp"},
      {"ashikhmin-shirley:rd=0.5,rs=0.5,nu=1,nv=1000", "anisotropic, half diffuse"},
      {"schlick:c=1,r=0.1", "white: the interreflection term's albedo grows at grazing"},
      {"schlick:c=1,r=0.5,p=0.1", "white, anisotropic"},
      {"schlick-phong:kd=0,ks=1,n=1", "rational Phong lobe, broad, all specular"},
      {"kajiya:kd=1,ks=0", "white fibres: Lambert across them, 1/(i.n) along"},
      {"kajiya:kd=0,ks=1,n=100", "fibre highlight cone alone"},
  };
  // Every analytic model at its defaults (measured models need a file: not here).
  std::vector<PlausibilityCase> out;
  for (const ModelInfo& info : model_catalogue())
    if (!info.make_with_file || info.file_optional) out.push_back({info.name, "defaults"});
  out.insert(out.end(), cases.begin(), cases.end());
  // Canonical specs, deduplicated, catalogue order first.
  std::vector<PlausibilityCase> unique;
  std::set<std::string> seen;
  for (const auto& c : out) {
    const std::string spec = c.spec == kIntensityForm ? c.spec : parse_model(c.spec)->spec();
    if (seen.insert(spec).second) unique.push_back({c.spec, c.note});
  }
  return unique;
}

PlausibilityRow measure_plausibility(const Model& model, const std::string& note, double tolerance) {
  PlausibilityRow row;
  row.spec = model.spec();
  row.note = note;
  row.declared = model.traits();
  const bool isotropic = row.declared.isotropic;
  const std::vector<double> azimuths_i = isotropic ? std::vector<double>{0.0} : std::vector<double>{0.0, 50.0};
  row.min_f = std::numeric_limits<double>::infinity();
  for (double pi_deg : azimuths_i)
    for (double ti : kThetas)
      for (double tj : kThetas)
        for (double p : kPhis) {
          const Vec3 i = dir(ti, pi_deg), j = dir(tj, pi_deg + p);
          const double a = model.f(i, j), b = model.f(j, i);
          if (a < row.min_f) {
            row.min_f = a;
            row.min_f_at = angles(ti, tj, p);
          }
          const double scale = std::max(std::abs(a), std::abs(b));
          if (scale > 1e-300) {
            const double v = std::abs(a - b) / scale;
            if (v > row.reciprocity_violation) {
              row.reciprocity_violation = v;
              row.reciprocity_at = angles(ti, tj, p);
            }
          }
        }
  CubatureOptions options;
  options.abs_tol = tolerance;
  row.max_albedo = -1.0;
  row.h_min = std::numeric_limits<double>::infinity();
  row.h_max = -row.h_min;
  for (double pi_deg : azimuths_i)
    for (double t : kIncidences) {
      const Estimate a = albedo(model, dir(t, pi_deg), options);
      const Estimate h = darkening(model, dir(t, pi_deg), options);
      row.converged = row.converged && a.converged && h.converged;
      row.evaluations += a.evaluations + h.evaluations;
      if (a.value > row.max_albedo) {
        row.max_albedo = a.value;
        row.max_albedo_error = a.error;
        row.max_albedo_theta_i = t;
      }
      row.h_min = std::min(row.h_min, h.value);
      row.h_max = std::max(row.h_max, h.value);
      row.h_error = std::max(row.h_error, h.error);
    }
  return row;
}

std::vector<PlausibilityRow> plausibility_report(double tolerance) {
  const std::vector<PlausibilityCase> cases = plausibility_cases();
  std::vector<PlausibilityRow> rows(cases.size());
  tbb::parallel_for(std::size_t{0}, cases.size(), [&](std::size_t k) {
    rows[k] = measure_plausibility(*make_case(cases[k].spec), cases[k].note, tolerance);
  });
  return rows;
}

namespace {
std::string sci(double x) {
  char buffer[32];
  if (x == 0.0) return "0";
  std::snprintf(buffer, sizeof buffer, std::abs(x) >= 1e-3 && std::abs(x) < 1e4 ? "%.4g" : "%.2e", x);
  return buffer;
}
const PlausibilityRow* find_row(const std::vector<PlausibilityRow>& rows, const std::string& prefix) {
  for (const auto& r : rows)
    if (r.spec.rfind(prefix, 0) == 0) return &r;
  return nullptr;
}
/// Every row whose albedo exceeds 1: such a surface reflects more light than it receives at that
/// incidence (energy creation), which a reader must see at once, not find in a table cell.
std::string energy_creation_section(const std::vector<PlausibilityRow>& rows) {
  std::ostringstream s;
  s << "## Energy created: albedo above 1\n\n";
  int count = 0;
  for (const auto& r : rows) {
    if (r.conserves()) continue;
    ++count;
    s << "- **`" << r.spec << "` creates energy**: a = " << sci(r.max_albedo) << " ± " << sci(r.max_albedo_error)
      << " at θ_i = " << sci(r.max_albedo_theta_i) << "°, i.e. it reflects " << sci(100.0 * (r.max_albedo - 1.0))
      << "% more than it receives there (declared " << to_string(r.declared.energy) << ").\n";
  }
  if (count == 0) s << "No row: every measured albedo is at most 1.\n";
  s << "\n";
  return s.str();
}
}  // namespace

std::string plausibility_markdown(const std::vector<PlausibilityRow>& rows, double tolerance,
                                  const std::string& command) {
  std::ostringstream s;
  s << "# Plausibility of every model, measured\n\n"
    << "<!-- Generated by `" << command << "`; do not edit by hand. -->\n\n"
    << "Koenderink & Pont (\"General Properties of BRDFs\") call a BRDF physically plausible when it is\n"
    << "non-negative, reciprocal (f(i, j) = f(j, i)) and conserves energy (albedo a(i) ≤ 1 for every\n"
    << "incidence). Each row measures these for one model and parameter set rather than trusting the\n"
    << "model's declared traits (`ganzfeld models`):\n\n"
    << "- **min f** over a grid of 8 polar angles per direction (0° to 89.9°) × 7 relative azimuths "
       "(× 2 azimuths of i for anisotropic models); *at* gives θ_i, θ_j, φ in degrees;\n"
    << "- **reciprocity**: max |f(i,j) − f(j,i)| / max(f(i,j), f(j,i)) over the same grid;\n"
    << "- **max a**: the largest albedo a(i) = ∫ (k·n) f(i,k) dk over θ_i ∈ {0, 15, …, 85, 89}°, by the "
       "cubature to "
    << sci(tolerance) << " (its error estimate in the JSON);\n"
    << "- **h range**: min and max of the law of darkening h(j) over the same angles — a sphere is "
       "invisible in a Ganzfeld exactly when h ≡ 1;\n"
    << "- **declared**: the traits the model claims; ✓ when the measurements agree with them "
       "(a claim of *plausible* needs f ≥ 0, reciprocity and a ≤ 1; *conserving* also h ≡ 1).\n\n"
    << "| model | note | min f (at) | reciprocity (at) | max a (at θ_i) | h range | invisible | declared | ✓ |\n"
    << "|---|---|---|---|---|---|---|---|---|\n";
  int inconsistent = 0;
  for (const auto& r : rows) {
    inconsistent += !r.traits_consistent();
    s << "| `" << r.spec << "` | " << r.note << " | " << sci(r.min_f) << " (" << r.min_f_at << ") | "
      << sci(r.reciprocity_violation) << (r.reciprocity_at.empty() ? "" : " (" + r.reciprocity_at + ")") << " | "
      << sci(r.max_albedo) << " (" << sci(r.max_albedo_theta_i) << "°) | " << sci(r.h_min) << " … " << sci(r.h_max)
      << " | " << (r.ganzfeld_invisible() ? "yes" : "no") << " | "
      << (r.declared.reciprocal ? "reciprocal" : "not reciprocal") << ", " << to_string(r.declared.energy) << " | "
      << (r.traits_consistent() ? "✓" : "✗") << (r.converged ? "" : " (not converged)") << " |\n";
  }
  s << "\n" << rows.size() << " rows; declared traits contradicted by the measurements: " << inconsistent << ".\n\n";
  s << energy_creation_section(rows);

  const PlausibilityRow* phong = find_row(rows, "phong:kd=0.2");
  const PlausibilityRow* lewis = find_row(rows, "phong-lewis:kd=0,");
  const PlausibilityRow* blinn = find_row(rows, "blinn-phong:kd=0,");
  const PlausibilityRow* intensity = find_row(rows, "blinn-phong, intensity form");
  s << "## K&P's claim: \"Phong and Blinn-Phong violate reciprocity\"\n\n"
    << "True of the models as their authors wrote them, false of the lobes themselves. Phong (1975) and\n"
    << "Blinn (1977) give a *reflected intensity*: the diffuse term is weighted by cos θ_i, the specular\n"
    << "term is not. Read as a BRDF (intensity divided by the irradiance ∝ cos θ_i), the specular part\n"
    << "acquires a factor 1/(i·n), which is not symmetric in i and j:\n\n";
  if (phong)
    s << "- original Phong, f = kd/π + ks cosⁿψ/(i·n): reciprocity violation " << sci(phong->reciprocity_violation)
      << " (at " << phong->reciprocity_at << "), max albedo " << sci(phong->max_albedo)
      << " at θ_i = " << sci(phong->max_albedo_theta_i) << "° (unbounded towards grazing);\n";
  if (intensity)
    s << "- Blinn's intensity form, f = kd/π + ks C (h·n)ⁿ/(i·n): violation " << sci(intensity->reciprocity_violation)
      << ", max albedo " << sci(intensity->max_albedo) << ".\n\n";
  s << "The lobes alone are symmetric: cos ψ = mirror(i)·j = mirror(j)·i and h·n is symmetric in i and\n"
    << "j, so the BRDF forms without the 1/(i·n) are reciprocal:\n\n";
  if (lewis)
    s << "- Lewis's normalized Phong, f = kd/π + ks (n+2)/(2π) cosⁿψ: violation " << sci(lewis->reciprocity_violation)
      << ";\n";
  if (blinn)
    s << "- Blinn-Phong as a BRDF, f = kd/π + ks C (h·n)ⁿ: violation " << sci(blinn->reciprocity_violation) << ".\n";
  s << "\n(Rounding alone gives violations of ~1e-16; the grid includes grazing angles, where 1/(i·n)\n"
    << "is regularized at 1e-6, see docs/models.md.)\n";
  return s.str();
}

}  // namespace ganzfeld
