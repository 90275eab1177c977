#include "cli/args.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <unistd.h>
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


/// Words joined into a line a POSIX shell reproduces: words with anything but [A-Za-z0-9_./:=,+-]
/// are single-quoted. The first word is written as `ganzfeld`.
std::string shell_line(const std::vector<std::string>& words) {
  std::string line = "ganzfeld";
  for (std::size_t k = 1; k < words.size(); ++k) {
    const std::string& word = words[k];
    const bool plain = !word.empty() && word.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                               "0123456789_./:=,+-") == std::string::npos;
    line += ' ';
    if (plain) {
      line += word;
    } else {
      line += '\'';
      for (char c : word) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
      line += '\'';
    }
  }
  return line;
}

/// "\rbaking g: 42% (55050/131072), 3 s left" on stderr, redrawn in place.
namespace {
class ProgressBar {
 public:
  explicit ProgressBar(std::string label) : label_(std::move(label)), start_(std::chrono::steady_clock::now()) {}
  void update(std::uint64_t done, std::uint64_t total) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double fraction = total ? static_cast<double>(done) / total : 1.0;
    const int percent = static_cast<int>(100.0 * fraction);
    if (percent == last_percent_ && done != total) return;
    last_percent_ = percent;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * fraction);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %3d%% (%llu/%llu)", label_.c_str(), bar.c_str(), percent,
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total));
    if (fraction > 0.0 && done != total) std::fprintf(stderr, " %.0f s left  ", elapsed * (1.0 - fraction) / fraction);
    if (done == total) std::fprintf(stderr, " %.1f s      \n", elapsed);
    std::fflush(stderr);
  }

 private:
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  int last_percent_ = -1;
};
}  // namespace

/// A progress bar for the bake of `law` of `spec` when stderr is a terminal and not --quiet.
void attach_progress(lut::BakeOptions& options, bool quiet, Law law, const std::string& spec) {
  if (quiet || !::isatty(STDERR_FILENO)) return;
  auto bar = std::make_shared<ProgressBar>(std::string("baking ") + to_string(law) + " of " + spec);
  options.progress = [bar](std::uint64_t done, std::uint64_t total) { bar->update(done, total); };
}

/// Creates the cache directory if its parent exists; refuses a missing parent, a non-directory
/// and an unwritable directory. Returns the directory.
std::string prepare_directory(const std::string& flag, const std::string& text) {
  namespace fs = std::filesystem;
  fs::path dir(text);
  if (text.empty()) throw InputError(flag + " is empty; expected a directory");
  if (!dir.has_filename() && dir.has_parent_path()) dir = dir.parent_path();  // "cache/" -> "cache"
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw InputError(flag + " '" + text + "' exists and is not a directory");
  } else {
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ec))
      throw InputError("cannot create " + flag + " '" + text + "': directory '" + parent.string() + "' does not exist");
    if (!fs::create_directory(dir, ec) && !fs::is_directory(dir))
      throw InputError("cannot create " + flag + " '" + text + "': " + ec.message());
  }
  if (::access(dir.c_str(), W_OK) != 0) throw InputError(flag + " '" + text + "' is not a writable directory");
  return dir.string();
}

lut::CacheResult bake_into_cache(const std::string& dir, const lut::TableRequest& request, const lut::BakeOptions& options,
                                 bool force) {
  const std::string path = lut::cache_path(dir, *request.model, request.law, options);
  // Stamped into the file: the single-table command that reproduces exactly this file.
  const std::string command = shell_line({"ganzfeld", "bake", "--model", request.spec, "--law", to_string(request.law),
                                          "--res", lut::resolution_text(options.resolution), "--tol",
                                          format_number(options.tolerance), "--encoding", lut::to_string(options.encoding),
                                          "--max-evals", std::to_string(options.max_evaluations), "-o", path});
  return lut::bake_or_reuse(path, *request.model, request.law, options, command, force);
}

SceneTables prepare_scene_tables(const Scene& scene, double tol, const std::string& cache, bool quiet) {
  SceneTables out;
  for (const lut::TableRequest& request : lut::tables_needed(scene)) {
    lut::BakeOptions options;
    options.resolution = request.law == Law::g ? std::vector<int>(lut::kSceneResG, lut::kSceneResG + 3)
                                               : std::vector<int>{lut::kSceneResH};
    options.tolerance = tol;
    attach_progress(options, quiet, request.law, request.spec);
    lut::Table table;
    std::string path, status = "baked";
    if (!cache.empty()) {
      lut::CacheResult result = bake_into_cache(cache, request, options);
      path = result.path;
      status = lut::to_string(result.status);
      table = std::move(result.table);
    } else {
      table = lut::bake(*request.model, request.law, options);
    }
    if (table.unconverged > 0)
      std::cerr << "ganzfeld: warning: " << table.unconverged << " entries of " << to_string(request.law) << " of "
                << request.spec << " missed tolerance " << format_number(tol) << " (max error "
                << format_number(table.max_error) << ")\n";
    nlohmann::ordered_json entry{{"model", request.spec}, {"law", to_string(request.law)}, {"status", status},
                                 {"max_error", table.max_error}};
    if (!path.empty()) entry["path"] = path;
    out.json.push_back(entry);
    out.tables[{request.spec, request.law}] = std::make_shared<const lut::Table>(std::move(table));
  }
  return out;
}

}  // namespace ganzfeld::cli
