#include "cli/args.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "laws/error.h"
#include "laws/registry.h"

namespace ganzfeld::cli {

using std::numbers::pi;

void DirectionArgs::add_to(CLI::App& app) {
  app.add_option("--i", i_text, "direction towards the source (sky pole for g), X,Y,Z in the local frame (n = +z)");
  app.add_option("--j", j_text, "direction towards the viewer, X,Y,Z in the local frame");
  app.add_option("--theta-i", theta_i, "polar angle of i from n in degrees (i at azimuth 0); up to 180 for g");
  app.add_option("--theta-j", theta_j, "polar angle of j from n in degrees, [0, 90]");
  app.add_option("--phi", phi_deg, "azimuth of j minus azimuth of i, degrees (default 0)");
}

Vec3 parse_vector(const std::string& flag, const std::string& text) {
  std::stringstream in(text);
  std::string part;
  double v[3];
  int count = 0;
  while (std::getline(in, part, ',')) {
    char* end = nullptr;
    const double x = std::strtod(part.c_str(), &end);
    if (count == 3 || part.empty() || *end != '\0' || !std::isfinite(x))
      throw InputError(flag + " '" + text + "' is not a direction; expected three finite numbers X,Y,Z");
    v[count++] = x;
  }
  if (count != 3) throw InputError(flag + " '" + text + "' is not a direction; expected three finite numbers X,Y,Z");
  const Vec3 d{v[0], v[1], v[2]};
  const double length = glm::length(d);
  if (!(length > 0.0) || !std::isfinite(length))
    throw InputError(flag + " '" + text + "' has zero length; expected a nonzero direction X,Y,Z");
  return d / length;
}

namespace {
void check_angle(const std::string& flag, double deg, double max_deg) {
  if (!std::isfinite(deg) || deg < 0.0 || deg > max_deg)
    throw InputError(flag + "=" + format_number(deg) + " is out of range; allowed: [0, " + format_number(max_deg) +
                     "] degrees");
}
}  // namespace

Vec3 DirectionArgs::incident(Law law) const {
  const bool sky = law == Law::g;
  const std::string allowed = sky ? "i·n in [-1, 1] for g" : "i·n >= 0 (above the surface)";
  Vec3 i;
  if (!i_text.empty()) {
    if (theta_i) throw InputError("give either --i or --theta-i, not both");
    i = parse_vector("--i", i_text);
    if (!sky && i.z < 0.0) throw InputError("--i '" + i_text + "' is below the surface; allowed: " + allowed);
  } else if (theta_i) {
    check_angle("--theta-i", *theta_i, sky ? 180.0 : 90.0);
    i = direction(*theta_i * pi / 180.0, 0.0);
  } else {
    throw InputError(std::string("law ") + to_string(law) + " needs the incident direction: give --i X,Y,Z or --theta-i DEG");
  }
  return i;
}

Vec3 DirectionArgs::outgoing(Law law) const {
  Vec3 j;
  if (!j_text.empty()) {
    if (theta_j) throw InputError("give either --j or --theta-j, not both");
    j = parse_vector("--j", j_text);
    if (j.z < 0.0) throw InputError("--j '" + j_text + "' is below the surface; allowed: j·n >= 0");
  } else if (theta_j) {
    check_angle("--theta-j", *theta_j, 90.0);
    if (!std::isfinite(phi_deg)) throw InputError("--phi=" + format_number(phi_deg) + " is not finite");
    j = direction(*theta_j * pi / 180.0, phi_deg * pi / 180.0);
  } else {
    throw InputError(std::string("law ") + to_string(law) + " needs the view direction: give --j X,Y,Z or --theta-j DEG [--phi DEG]");
  }
  return j;
}

void validate_tolerance(double tol) {
  if (!std::isfinite(tol) || tol < 1e-15 || tol > 1.0)
    throw InputError("--tol=" + format_number(tol) + " is not allowed; expected an absolute tolerance in [1e-15, 1]");
}


}  // namespace ganzfeld::cli
