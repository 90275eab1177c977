#include "cli/args.h"

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <sstream>

#include "models/registry.h"
#include "util/error.h"
#include "util/progress.h"

namespace ganzfeld::cli {

using std::numbers::pi;

void DirectionArgs::add_to(CLI::App& app) {
  app.add_option("--i", i_text, "direction towards the source (sky pole for g), X,Y,Z in the local frame (n = +z)");
  app.add_option("--j", j_text, "direction towards the viewer, X,Y,Z in the local frame");
  app.add_option("--theta-i", theta_i, "polar angle of i from n in degrees (i at azimuth 0); up to 180 for g");
  app.add_option("--theta-j", theta_j, "polar angle of j from n in degrees, [0, 90]");
  app.add_option("--phi", phi_deg, "azimuth of j minus azimuth of i, degrees (default 0)");
}

void ParameterArgs::add_to(CLI::App& app) {
  app.add_option("--alpha", alpha, "GGX-style roughness alpha in (0, 1] (overrides the model's / picks the table row)");
  app.add_option("--roughness", roughness, "perceptual roughness R in [0, 1], alpha = R^2 (instead of --alpha)");
}

std::optional<std::pair<std::string, double>> ParameterArgs::given() const {
  if (alpha && roughness) throw InputError("give either --alpha or --roughness, not both");
  if (alpha && !(*alpha > 0.0 && *alpha <= 1.0))
    throw InputError("--alpha=" + format_number(*alpha) + " is not allowed; allowed: a real number in (0, 1]");
  if (roughness && !(*roughness >= 0.0 && *roughness <= 1.0))
    throw InputError("--roughness=" + format_number(*roughness) + " is not allowed; allowed: a real number in [0, 1]");
  if (alpha) return std::pair<std::string, double>{"alpha", *alpha};
  if (roughness) return std::pair<std::string, double>{"roughness", *roughness};
  return std::nullopt;
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
    throw InputError(std::string("law ") + to_string(law) +
                     " needs the incident direction: give --i X,Y,Z or --theta-i DEG");
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
    throw InputError(std::string("law ") + to_string(law) +
                     " needs the view direction: give --j X,Y,Z or --theta-j DEG [--phi DEG]");
  }
  return j;
}

void add_json_flag(CLI::App& cmd, bool& json, const std::string& shape) {
  cmd.add_flag("--json", json, "print one JSON document" + (shape.empty() ? "" : ": " + shape));
}

void add_model_option(CLI::App& cmd, std::string& spec) {
  cmd.add_option("--model", spec, "model spec, e.g. specular:alpha=8 (see `ganzfeld models`)")->required();
}

void add_table_argument(CLI::App& cmd, std::string& path) {
  cmd.add_option("FILE", path, "table written by `ganzfeld bake`")->required();
}

void validate_tolerance(double tol) { check_tolerance("tol", tol); }

/// Words joined into a line a POSIX shell reproduces: words with anything but [A-Za-z0-9_./:=,+-]
/// are single-quoted. The first word is written as `ganzfeld`.
std::string shell_line(const std::vector<std::string>& words) {
  std::string line = "ganzfeld";
  for (std::size_t k = 1; k < words.size(); ++k) {
    const std::string& word = words[k];
    const bool plain = !word.empty() && word.find_first_not_of(
                                            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
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

/// A progress bar for the bake of `law` of `spec` when stderr is a terminal and not --quiet.
void attach_progress(tables::BakeCommon& options, bool quiet, Law law, const std::string& spec) {
  options.progress = util::progress_bar(std::string("baking ") + to_string(law) + " of " + spec, quiet);
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

void check_max_evaluations(long long n) { ganzfeld::check_max_evaluations("max_evals", n); }

TableOptionArgs::Added TableOptionArgs::add_to(CLI::App& app, const scene::TableOptions& defaults, bool per_law_grids) {
  if (per_law_grids) {
    app.add_option(
        "--res-g", res_g,
        "nodes of every g table, NIxNJxNPHI (default " + tables::resolution_text(defaults.resolution_g) + ")");
    app.add_option("--res-h", res_h,
                   "nodes of every h table (default " + tables::resolution_text(defaults.resolution_h) + ")");
  }
  Added added{};
  added.tol = app.add_option(
      "--tol", tol,
      "absolute tolerance of every table entry's cubature (default " + format_number(defaults.tolerance) + ")");
  app.add_option("--encoding", encoding,
                 "stored precision of the tables: float (default), half, or unorm16 (16-bit codes over the table's "
                 "range, docs/lut-format.md)");
  app.add_option("--max-evals", max_evaluations,
                 "evaluation budget per table entry; beyond it the entry is kept and counted as unconverged");
  added.max_error = app.add_option(
      "--max-error", max_error,
      "bake every table to this validated lookup error: the baker chooses resolution, axes, interpolation "
      "and tolerance (excludes --res, --res-g, --res-h, --tol)");
  added.max_bytes = app.add_option("--max-bytes", max_bytes,
                                   "with --max-error: cap of each table's value bytes (default " +
                                       std::to_string(tables::kDefaultMaxValueBytes) +
                                       "); refused when the error cannot be met within it");
  added.fetches = app.add_option(
      "--fetches", fetches,
      "with --max-error: texture fetches one lookup of a table may cost a shader, N >= 1 (1: one "
      "hardware-filtered fetch, its bound covering 8-bit filter weights); the cheapest scheme within N is "
      "baked (default: " +
          (defaults.target
               ? "with no accuracy option scenes bake to --max-error " + format_number(defaults.target->lookup_error) +
                     " --fetches " + std::to_string(defaults.target->max_fetches) +
                     (defaults.target->best_effort ? " --best-effort" : "") +
                     "; a scene's --max-error alone searches within " + std::to_string(scene::kSceneSearchFetches) +
                     "; "
               : std::string()) +
          "one table: no budget, the fewest value bytes)");
  app.add_flag(
      "--best-effort", best_effort,
      "with --max-error: where no scheme within the budget reaches it, keep the most accurate table the "
      "search baked (its stated lookup error is the miss) instead of refusing" +
          std::string(defaults.target && defaults.target->best_effort ? " (the scene defaults are best effort)" : ""));
  return added;
}

namespace {
/// parse_resolution with its refusal naming `parameter` (res_g, res_h) instead of res.
std::vector<int> resolution_for(const std::string& parameter, const std::string& text, Law law) {
  try {
    return tables::parse_resolution(text, law);
  } catch (const InputError& e) { throw e.renamed("res", parameter); }
}
}  // namespace

void TableOptionArgs::check_target_parts() const {
  if (max_error) return;
  if (max_bytes) throw tables::needs_target("max_bytes");
  if (fetches) throw tables::needs_target("fetches");
  if (best_effort) throw tables::needs_target("best_effort");
}

scene::TableOptions TableOptionArgs::options(const scene::TableOptions& defaults) const {
  scene::TableOptions out = defaults;
  if (!res_g.empty()) out.resolution_g = resolution_for("res_g", res_g, Law::g);
  if (!res_h.empty()) out.resolution_h = resolution_for("res_h", res_h, Law::h);
  if (tol) out.tolerance = *tol;
  validate_tolerance(out.tolerance);
  if (!encoding.empty()) out.encoding = tables::parse_encoding(encoding);
  if (max_evaluations) out.max_evaluations = *max_evaluations;
  check_max_evaluations(out.max_evaluations);
  check_target_parts();
  if (fetches) tables::check_fetch_budget(*fetches);
  const Named target{"max_error"};
  const bool fixed = !res_g.empty() || !res_h.empty() || tol;
  if (max_error) {
    if (fixed)
      throw InputError({target, " chooses the resolution and the tolerance itself; drop ",
                        Named{!res_g.empty()   ? "res_g"
                              : !res_h.empty() ? "res_h"
                                               : "tol"},
                        " or ", target});
    // E here; B against the smallest table of each table's own law when it is keyed (bake, table_key).
    tables::check_error_target(*max_error, 0, Law::g, out.encoding);
    const bool budgeted_defaults = defaults.target && defaults.target->max_fetches;
    const int budget = fetches             ? static_cast<int>(std::min<long long>(*fetches, 1 << 20))
                       : budgeted_defaults ? scene::kSceneSearchFetches
                                           : 0;
    // A target asked for is met or refused, unless --best-effort.
    out.target = tables::ErrorTarget{*max_error, max_bytes.value_or(0), budget, best_effort};
  } else if (fixed) {  // a resolution or tolerance asked for: no search
    out.target.reset();
  }
  return out;
}

scene::TableStore table_store(const std::string& cache_dir, bool quiet, bool force) {
  scene::TableStore store;
  store.cache_dir = cache_dir;
  store.force = force;
  store.command_line = shell_line;
  store.before_bake = [quiet](scene::TableRequest& request) {
    attach_progress(tables::common(request.options), quiet, request.law, request.spec);
  };
  return store;
}

void CacheArgs::add_to(CLI::App& app, const std::string& when) {
  const std::string help =
      "reuse tables from DIR and store new ones there (created if its parent exists); the files of `ganzfeld bake "
      "scene SCENE --out DIR`. Default: bake in memory";
  app.add_option("--cache", dir, when + help);
}

scene::TableStore CacheArgs::store(bool quiet) const {
  return table_store(dir.empty() ? std::string() : prepare_directory("--cache", dir), quiet);
}

nlohmann::ordered_json tables_json(const scene::ShadingPlan& plan) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const scene::PlannedTable& t : plan.tables)
    out.push_back(shapes::table_json(t.path, *t.table, t.status, t.seconds));
  return out;
}

void warn_unconverged(const tables::Table& t, tables::CacheStatus status) {
  if (status != tables::CacheStatus::baked || t.unconverged == 0) return;
  std::cerr << "ganzfeld: warning: " << t.unconverged << " of " << t.entries() << " entries of " << to_string(t.law)
            << " of " << t.model << " did not reach tolerance " << format_number(t.tolerance)
            << " within the evaluation budget; their achieved error is stored (max error "
            << format_number(t.node_error) << ")\n";
}

void warn_unconverged(const scene::ShadingPlan& plan) {
  for (const scene::PlannedTable& t : plan.tables) warn_unconverged(*t.table, t.status);
}

}  // namespace ganzfeld::cli
