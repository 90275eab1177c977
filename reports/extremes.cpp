#include "reports/extremes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <nlohmann/json.hpp>

#include "models/registry.h"
#include "models/spec.h"
#include "reference/lune_reference.h"
#include "util/error.h"
#include "util/names.h"
#include "util/timing.h"

namespace ganzfeld {

namespace {

using std::numbers::pi;

/// Rounding allowed on top of both error estimates: the engine and the reference each sum ~10^4
/// panel values, so their last bits differ by ~10^4 ulps of the result (~1e-12 relative); the
/// 1e-13 of tests/independent_reference_test.cpp, relative to the value when it exceeds 1.
constexpr double kRoundingSlack = 1e-13;

// The grid: cosines of the incident direction (sky pole) and of the view, azimuths
// of the view about n.
constexpr double kIncidentCos[] = {-1.0, -0.999, 0.0, 1e-9, 1e-6, 1.0};
constexpr double kViewCos[] = {0.0, 1e-9, 1e-6, 1.0};
constexpr double kPhi[] = {0.0, pi / 2, pi};
/// The halfway-vector-disk models' own extremes: theta_o = 89.99 degrees and j·n = 1e-4, where
/// their lumps are thinnest (docs/hvd.md).
const double kHvdViewCos[] = {1e-4, std::cos(89.99 * pi / 180)};
// The quick slice (ctest): the corners that break the most.
constexpr double kQuickIncidentCos[] = {-0.999, 1e-6, 1.0};
constexpr double kQuickViewCos[] = {1e-6, 1.0};
constexpr double kQuickPhi[] = {pi / 2};

/// Extra specs beyond each parameter's ends: shapes no single parameter at an end makes.
struct Extra {
  const char* model;
  const char* spec;
  const char* why;
};
constexpr Extra kExtras[] = {
    {"hvd-empirical", "hvd-empirical:ns=1000,rsu=1,rsv=0.1,rru=0.1,rrv=1,k=0.5", "anisotropic radii, sharp"},
    {"hvd-empirical", "hvd-empirical:rsu=0.001,rsv=1,k=1,nr=1000", "anisotropic radii, retro only"},
    {"ggx", "ggx:alpha_x=0.001,alpha_y=1", "anisotropic, alpha ends"},
    {"ward-aniso", "ward-aniso:alpha_x=0.01,alpha_y=1", "anisotropic, alpha ends"},
    {"ashikhmin-shirley", "ashikhmin-shirley:nu=0,nv=1000", "anisotropic, exponent ends"},
    {"schlick", "schlick:r=0.001,p=0.001", "sharp and anisotropic ends"},
    {"mixture", "0.5*lambert+0.5*specular:alpha=1000", "diffuse + sharp specular"},
    {"mixture", "0.3*hvd-empirical:k=0.5+0.4*ggx:alpha=0.01+0.3*asperity:alpha=1000", "three families"},
};

bool wanted(const ExtremesOptions& options, const std::string& model) {
  return options.models.empty() ||
         std::find(options.models.begin(), options.models.end(), model) != options.models.end();
}

/// A parameter's ends as spec values: min (just above it when excluded), max capped for exponents.
std::vector<std::pair<std::string, std::string>> ends(const ParamInfo& p) {
  if (p.type == ParamType::choice) return {{"min", p.choices.front()}, {"max", p.choices.back()}};
  const double lo = p.min_exclusive ? p.min + 1e-3 * (p.max - p.min) : p.min;
  const double hi = std::min(p.max, std::max(lo, kExtremesExponentCap));
  return {{"min", format_number(lo)}, {"max", format_number(hi)}};
}

}  // namespace

std::vector<ExtremesSpec> extremes_specs(const ExtremesOptions& options) {
  std::vector<ExtremesSpec> out;
  for (const ModelInfo& m : model_catalogue()) {
    if (m.make_with_file && !m.file_optional) continue;  // measured: needs a data file
    if (!wanted(options, m.name)) continue;
    out.push_back({m.name, m.name, "default"});
    if (options.quick || options.defaults_only) continue;
    for (const ParamInfo& p : m.parameters)
      for (const auto& [end, value] : ends(p))
        out.push_back({m.name, m.name + ":" + p.name + "=" + value, p.name + " " + end});
  }
  for (const Extra& e : kExtras)
    if (wanted(options, e.model) && (!options.quick || std::string(e.model) == "mixture"))
      out.push_back({e.model, e.spec, e.why});
  return out;
}

namespace {

/// A case a reference judged: g, h or a, finite, converged and resolved.
bool judged(const ExtremesCase& c) { return c.law != Law::f && c.finite && c.converged && !c.reference_unresolved; }

double judging_resolution(double engine_tolerance, double reference) {
  return engine_tolerance * std::max(1.0, std::abs(reference));
}

bool honest(double value, double error, double reference, double reference_error) {
  return std::abs(value - reference) <= error + reference_error + kRoundingSlack * std::max(1.0, std::abs(reference));
}

enum class ReferenceRule { gauss_kronrod_61, gauss_kronrod_31_swapped, tanh_sinh, tanh_sinh_about_antipode };

constexpr std::array<util::EnumName<ReferenceRule>, 4> kRuleNames{
    {{ReferenceRule::gauss_kronrod_61, "gauss_kronrod<61>"},
     {ReferenceRule::gauss_kronrod_31_swapped, "gauss_kronrod<31>, swapped"},
     {ReferenceRule::tanh_sinh, "tanh_sinh"},
     {ReferenceRule::tanh_sinh_about_antipode, "tanh_sinh, about the antipode"}}};

reference::Value reference_law(const Model& model, Law law, const Vec3& i, const Vec3& j, ReferenceRule rule,
                               double engine_tolerance) {
  reference::Options options;
  // A tenth of the engine's tolerance: enough to judge it, without asking 1e-10 of a value whose
  // kink or horizon layer makes each digit cost a bisection level.
  options.absolute_tolerance = 0.1 * engine_tolerance;
  options.swapped = rule == ReferenceRule::gauss_kronrod_31_swapped;
  options.tanh_sinh = rule == ReferenceRule::tanh_sinh;
  options.about_antipode = rule == ReferenceRule::tanh_sinh_about_antipode;
  options.max_evaluations = options.tanh_sinh        ? kExtremesTanhSinhBudget
                            : options.about_antipode ? kExtremesAntipodeBudget
                                                     : kExtremesReferenceBudget;
  switch (law) {
    case Law::g: return reference::vignetting(model, i, j, options);
    case Law::h: return reference::darkening(model, j, options);
    case Law::a: return reference::albedo(model, i, options);
    default: return {model.f(i, j), 0.0, 0.0};  // f is not judged (judge_case)
  }
}

}  // namespace

namespace {

// The references in the order they are tried; the first resolved one of the first kExtremesJudges
// judges, the others are computed only when needed (they are far costlier than the engine). The
// last, tanh_sinh about the antipode, is a witness only: it resolves the 1/|k + fixed| point of a
// microfacet lobe at a grazing view, where tanh_sinh on the lune is up to 1e-7 off, but is itself
// confidently 4e-8 off on hvd-empirical's ridge along a lune's edge (tests/extremes_test.cpp).
constexpr std::array<ReferenceRule, kExtremesReferences> kOrder{
    ReferenceRule::gauss_kronrod_61, ReferenceRule::gauss_kronrod_31_swapped, ReferenceRule::tanh_sinh,
    ReferenceRule::tanh_sinh_about_antipode};

}  // namespace

void judge_against_references(ExtremesCase& c, const std::function<const reference::Value&(std::size_t)>& get,
                              double engine_tolerance) {
  // A reference resolves the case when its stated error is within the engine's tolerance, scaled
  // by |value| where that exceeds 1: a nested rule summing millions of nodes states ~1e-10 of the
  // value at best (reference/lune_reference.h asks 1e-10 relative), so on a value of 1e5 no
  // reference resolves 1e-8 absolute, and such a case is judged at the resolution the value allows
  // (extremes_markdown counts them).
  auto resolved = [&](const reference::Value& r) {
    return r.resolved && std::isfinite(r.value) && r.total_error() <= judging_resolution(engine_tolerance, r.value);
  };
  std::size_t judging = 0;
  while (judging < kExtremesJudges && !resolved(get(judging))) ++judging;
  const bool none_resolved = judging == kExtremesJudges;
  bool lone_refuter = false;
  if (none_resolved) {
    // None resolves the tolerance. An unresolved bound can be wrong: tanh_sinh's across a kink
    // inside its panel (schlick-phong's a at i·n = 0.3: 4.7e-7 off with 1.7e-8 stated, where both
    // Gauss–Kronrod references agree with the engine) or at a lune's tip where a grazing lobe sits
    // (hvd-empirical's g at i·n = 0, θ_o = 89.99°, φ = 90°: 0.16 off with 0.08 stated, where g = h/2
    // by the mirror symmetry of an isotropic model agrees with the engine). So unresolved references
    // refute the engine only as two that exclude its value and agree with each other (the closer
    // bound of the pair judges); two that exclude each other too are no more than one. A lone
    // refuter makes the case "references disagree" where another agrees with the engine and excludes
    // it, and leaves it unresolved otherwise (tests/extremes_test.cpp).
    std::vector<std::size_t> refuters;
    for (std::size_t k = 0; k < kExtremesReferences; ++k)
      if (get(k).resolved && std::isfinite(get(k).value) &&
          !honest(c.engine.value, c.engine.error, get(k).value, get(k).total_error()))
        refuters.push_back(k);
    auto closer = [&](std::optional<std::size_t> best, std::size_t k) {
      return !best || get(k).total_error() < get(*best).total_error() ? std::optional(k) : best;
    };
    std::optional<std::size_t> refuting, closest;
    for (std::size_t a = 0; a < refuters.size(); ++a) {
      closest = closer(closest, refuters[a]);
      for (std::size_t b = a + 1; b < refuters.size(); ++b) {
        const reference::Value &first = get(refuters[a]), &second = get(refuters[b]);
        if (honest(first.value, first.total_error(), second.value, second.total_error()))
          refuting = closer(closer(refuting, refuters[a]), refuters[b]);
      }
    }
    lone_refuter = !refuting && closest;
    if (!refuting) refuting = closest;
    c.reference_unresolved = !refuting;
    judging = refuting.value_or(0);
  }
  const reference::Value& ref = get(judging);
  c.reference = ref.value;
  c.reference_error = ref.total_error();
  c.reference_rule = util::name_of(kRuleNames, kOrder[judging]);
  if (c.reference_unresolved || honest(c.engine.value, c.engine.error, c.reference, c.reference_error)) return;
  // The engine disagrees with the judging reference: another resolved reference (any finite one,
  // when none resolved) that agrees with it makes the case "references disagree"; none makes it
  // dishonest.
  c.dishonest = true;
  for (std::size_t k = 0; k < kExtremesReferences; ++k) {
    const bool usable = none_resolved ? get(k).resolved && std::isfinite(get(k).value) &&
                                            !honest(get(k).value, get(k).total_error(), ref.value, ref.total_error())
                                      : resolved(get(k));
    if (k == judging || !usable) continue;
    c.second_reference = get(k).value;
    c.second_reference_error = get(k).total_error();
    if (honest(c.engine.value, c.engine.error, c.second_reference, c.second_reference_error)) {
      c.dishonest = false;
      c.references_disagree = true;
      break;
    }
  }
  if (c.dishonest && lone_refuter) {
    c.dishonest = false;
    c.reference_unresolved = true;
  }
}

ExtremesCase judge_case(const Model& model, Law law, const Vec3& i, const Vec3& j, double engine_tolerance,
                        long long engine_budget) {
  ExtremesCase c;
  c.spec = model.spec();
  c.law = law;
  c.i = i;
  c.j = j;
  CubatureOptions options;
  options.abs_tol = engine_tolerance;
  options.max_evaluations = engine_budget;
  c.engine = evaluate_law(model, law, i, j, options);
  c.finite = std::isfinite(c.engine.value);
  c.converged = c.engine.converged;
  // f is the formula itself (error 0): only its finiteness is judged. Compared with f at the
  // unnormalized directions it would measure the formula's conditioning at grazing (1/(i·n)
  // factors turn the last bit of a direction into 1e-10 relative), not an estimate's honesty.
  if (law == Law::f || !c.finite || !c.converged) return c;
  std::array<std::optional<reference::Value>, kExtremesReferences> computed;
  judge_against_references(
      c,
      [&](std::size_t k) -> const reference::Value& {
        if (!computed[k]) computed[k] = reference_law(model, law, i, j, kOrder[k], engine_tolerance);
        return *computed[k];
      },
      engine_tolerance);
  return c;
}

namespace {

struct Job {
  std::size_t spec;  // index into the specs
  ModelPtr model;
  Law law;
  Vec3 i, j;
  std::string where;
};

std::string where_text(Law law, double cos_i, double cos_j, double phi) {
  std::ostringstream s;
  s.precision(4);
  if (law != Law::h) s << "i·n=" << cos_i;
  if (law != Law::a) s << (law != Law::h ? ", " : "") << "j·n=" << cos_j;
  s << ", φ=" << phi * 180 / pi << "°";
  return s.str();
}

/// The cases of one model: the grid for each law, without repeats (an isotropic model's laws
/// depend on i·n, j·n and i·j only; h and a on one direction only).
void add_jobs(std::size_t spec, const ModelPtr& model, bool hvd, bool quick, std::vector<Job>& jobs) {
  std::vector<double> incident(std::begin(kIncidentCos), std::end(kIncidentCos));
  std::vector<double> view(std::begin(kViewCos), std::end(kViewCos)), phis(std::begin(kPhi), std::end(kPhi));
  if (hvd) view.insert(view.end(), std::begin(kHvdViewCos), std::end(kHvdViewCos));
  if (quick) {
    incident.assign(std::begin(kQuickIncidentCos), std::end(kQuickIncidentCos));
    view.assign(std::begin(kQuickViewCos), std::end(kQuickViewCos));
    phis.assign(std::begin(kQuickPhi), std::end(kQuickPhi));
  }
  const bool isotropic = model->traits().isotropic;
  std::set<std::array<double, 7>> seen;
  auto add = [&](Law law, double ci, double cj, double phi) {
    const Vec3 i = law == Law::a ? direction_from_cos(ci, phi) : direction_from_cos(ci, 0.0);
    const Vec3 j = direction_from_cos(cj, phi);
    const Vec3 i_used = law == Law::h ? Vec3{0, 0, 1} : i, j_used = law == Law::a ? Vec3{0, 0, 1} : j;
    const std::array<double, 7> key =
        isotropic ? std::array<double, 7>{double(law), i_used.z, j_used.z, glm::dot(i_used, j_used), 0, 0, 0}
                  : std::array<double, 7>{double(law), i_used.x, i_used.y, i_used.z, j_used.x, j_used.y, j_used.z};
    if (seen.insert(key).second) jobs.push_back({spec, model, law, i_used, j_used, where_text(law, ci, cj, phi)});
  };
  for (double phi : phis) {
    for (double ci : incident)
      for (double cj : view) add(Law::f, ci, cj, phi), add(Law::g, ci, cj, phi);
    for (double cj : view) add(Law::h, 1.0, cj, phi);
    for (double ci : incident)
      if (ci >= 0.0) add(Law::a, ci, 1.0, phi);
  }
}

/// Counts one case into its model's row (and keeps it among the flagged when it is not plainly honest).
void add_case(ExtremesRow& row, ExtremesCase c) {
  ++row.cases;
  row.seconds += c.seconds;
  row.non_finite += !c.finite;
  row.not_converged += c.finite && !c.converged;
  row.dishonest += c.dishonest;
  row.references_disagree += c.references_disagree;
  row.unresolved += c.reference_unresolved;
  row.judged_by_fallback += judged(c) && c.reference_rule != "gauss_kronrod<61>";
  if (!c.finite || !c.converged || c.dishonest || c.references_disagree || c.reference_unresolved)
    row.flagged.push_back(c);
  row.all.push_back(std::move(c));
}

}  // namespace

std::vector<ExtremesRow> extremes_report(const ExtremesOptions& options) {
  const std::vector<ExtremesSpec> specs = extremes_specs(options);
  std::vector<ExtremesRow> rows;
  std::map<std::string, std::size_t> row_of;
  std::vector<Job> jobs;
  for (std::size_t s = 0; s < specs.size(); ++s) {
    if (!row_of.count(specs[s].model)) {
      row_of[specs[s].model] = rows.size();
      ExtremesRow row;
      row.model = specs[s].model;
      rows.push_back(row);
    }
    ExtremesRow& row = rows[row_of[specs[s].model]];
    try {
      const ModelPtr model = parse_model(specs[s].spec);
      ++row.specs;
      add_jobs(s, model, specs[s].model.rfind("hvd", 0) == 0, options.quick, jobs);
    } catch (const InputError& e) { row.refused.push_back(specs[s].spec + " (" + e.what() + ")"); }
  }
  std::vector<ExtremesCase> results(jobs.size());
  std::mutex reporting;
  std::size_t done = 0;
  tbb::parallel_for(std::size_t{0}, jobs.size(), [&](std::size_t k) {
    const util::Stopwatch watch;
    results[k] = judge_case(*jobs[k].model, jobs[k].law, jobs[k].i, jobs[k].j, options.engine_tolerance);
    results[k].where = jobs[k].where;
    results[k].seconds = watch.seconds();
    if (!options.on_case) return;
    const std::lock_guard lock(reporting);
    options.on_case(results[k], ++done, jobs.size());
  });
  for (std::size_t k = 0; k < jobs.size(); ++k)
    add_case(rows[row_of[specs[jobs[k].spec].model]], std::move(results[k]));
  return rows;
}

std::vector<std::string> extremes_models(const ExtremesOptions& options) {
  std::vector<std::string> models;
  for (const ExtremesSpec& s : extremes_specs(options))
    if (std::find(models.begin(), models.end(), s.model) == models.end()) models.push_back(s.model);
  return models;
}

namespace {

nlohmann::ordered_json vector_json(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 vector_of(const nlohmann::json& v) {
  return {v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>()};
}

nlohmann::ordered_json options_json(const ExtremesOptions& options) {
  return {{"tolerance", options.engine_tolerance}, {"quick", options.quick}, {"defaults_only", options.defaults_only}};
}

}  // namespace

nlohmann::ordered_json extremes_case_json(const ExtremesCase& c) {
  return {{"spec", c.spec},
          {"law", to_string(c.law)},
          {"i", vector_json(c.i)},
          {"j", vector_json(c.j)},
          {"where", c.where},
          {"value", c.engine.value},
          {"error", c.engine.error},
          {"evaluations", c.engine.evaluations},
          {"engine_converged", c.engine.converged},
          {"reference", c.reference},
          {"reference_error", c.reference_error},
          {"reference_rule", c.reference_rule},
          {"second_reference", c.second_reference},
          {"second_reference_error", c.second_reference_error},
          {"finite", c.finite},
          {"converged", c.converged},
          {"dishonest", c.dishonest},
          {"references_disagree", c.references_disagree},
          {"reference_unresolved", c.reference_unresolved},
          {"seconds", c.seconds}};
}

std::string extremes_row_json(const ExtremesRow& row, const ExtremesOptions& options, double wall_seconds) {
  nlohmann::ordered_json cases = nlohmann::ordered_json::array();
  for (const ExtremesCase& c : row.all) cases.push_back(extremes_case_json(c));
  const nlohmann::ordered_json doc{{"model", row.model},     {"options", options_json(options)}, {"specs", row.specs},
                                   {"refused", row.refused}, {"wall_seconds", wall_seconds},     {"cases", cases}};
  return doc.dump(1) + "\n";
}

KeptExtremesRow extremes_row_from_json(const std::string& text, const ExtremesOptions& options,
                                       const std::string& path) {
  auto refuse = [&](const std::string& why) {
    throw InputError("kept extremes row '" + path + "': " + why + " (delete it to measure the model again)");
  };
  KeptExtremesRow kept;
  try {
    const nlohmann::json doc = nlohmann::json::parse(text);
    if (doc.at("options") != nlohmann::json(options_json(options)))
      refuse("measured with options " + doc.at("options").dump() + ", this run's are " + options_json(options).dump());
    kept.row.model = doc.at("model").get<std::string>();
    kept.row.specs = doc.at("specs").get<int>();
    kept.row.refused = doc.at("refused").get<std::vector<std::string>>();
    kept.wall_seconds = doc.at("wall_seconds").get<double>();
    // JSON has no infinity or NaN: the writer's null is an infinite error (errors are >= 0) or a
    // value that is not a number.
    auto number = [](const nlohmann::json& x, double if_null) { return x.is_null() ? if_null : x.get<double>(); };
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    for (const auto& j : doc.at("cases")) {
      ExtremesCase c;
      c.spec = j.at("spec").get<std::string>();
      c.law = parse_law(j.at("law").get<std::string>());
      c.i = vector_of(j.at("i"));
      c.j = vector_of(j.at("j"));
      c.where = j.at("where").get<std::string>();
      c.engine = {number(j.at("value"), kNaN), number(j.at("error"), kInfinity), j.at("evaluations").get<long long>(),
                  j.at("engine_converged").get<bool>()};
      c.reference = number(j.at("reference"), kNaN);
      c.reference_error = number(j.at("reference_error"), kInfinity);
      c.reference_rule = j.at("reference_rule").get<std::string>();
      c.second_reference = number(j.at("second_reference"), kNaN);
      c.second_reference_error = number(j.at("second_reference_error"), kInfinity);
      c.finite = j.at("finite").get<bool>();
      c.converged = j.at("converged").get<bool>();
      c.dishonest = j.at("dishonest").get<bool>();
      c.references_disagree = j.at("references_disagree").get<bool>();
      c.reference_unresolved = j.at("reference_unresolved").get<bool>();
      c.seconds = j.at("seconds").get<double>();
      add_case(kept.row, std::move(c));
    }
  } catch (const nlohmann::json::exception& e) { refuse(std::string("not an extremes row: ") + e.what()); }
  return kept;
}

namespace {

std::string number(double x, int digits = 3) {
  std::ostringstream s;
  s.precision(digits);
  s << x;
  return s.str();
}

int tbb_threads() { return tbb::this_task_arena::max_concurrency(); }

std::string verdict(const ExtremesCase& c) {
  if (!c.finite) return "non-finite";
  if (!c.converged) return "not converged";
  if (c.reference_unresolved) return "reference unresolved";
  if (c.dishonest) return "dishonest";
  if (c.references_disagree) return "references disagree";
  return "honest";
}

/// Flagged cases shown in the page per kind when not all are (the CSV holds every case).
constexpr std::size_t kShownPerKind = 25;

void case_rows(std::ostringstream& md, const std::vector<ExtremesCase>& cases) {
  md << "| spec | law | where | engine ± estimate | reference ± error (rule) | second reference ± error | verdict |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const ExtremesCase& c : cases) {
    const bool judged = c.finite && c.converged;
    const bool second = c.dishonest || c.references_disagree;
    md << "| `" << c.spec << "` | " << to_string(c.law) << " | " << c.where << " | " << number(c.engine.value, 12)
       << " ± " << number(c.engine.error, 2) << " | "
       << (judged ? number(c.reference, 12) + " ± " + number(c.reference_error, 2) + " (" + c.reference_rule + ")"
                  : std::string("—"))
       << " | "
       << (second ? number(c.second_reference, 12) + " ± " + number(c.second_reference_error, 2) : std::string("—"))
       << " | " << verdict(c) << " |\n";
  }
}

/// One kind of flagged case: every one when few, else the worst (`worse` orders them) and a count.
template <class Worse>
void flagged_kind(std::ostringstream& md, const std::vector<ExtremesRow>& rows, const std::string& kind,
                  const std::string& heading, Worse worse) {
  std::vector<ExtremesCase> cases;
  for (const auto& r : rows)
    for (const ExtremesCase& c : r.flagged)
      if (verdict(c) == kind) cases.push_back(c);
  md << "\n### " << heading << " (" << cases.size() << ")\n\n";
  if (cases.empty()) {
    md << "None.\n";
    return;
  }
  std::stable_sort(cases.begin(), cases.end(), worse);
  if (cases.size() > kShownPerKind) {
    md << "The " << kShownPerKind << " worst of " << cases.size() << " (every one is in the CSV):\n\n";
    cases.resize(kShownPerKind);
  }
  case_rows(md, cases);
}

/// Where the flagged cases of one kind lie: counts per law and position class of the grid.
void where_counts(std::ostringstream& md, const std::vector<ExtremesRow>& rows, const std::string& kind) {
  std::map<std::string, int> counts;
  for (const auto& r : rows)
    for (const ExtremesCase& c : r.flagged)
      if (verdict(c) == kind) {
        std::string where = c.where.substr(0, c.where.find(", φ="));
        ++counts[std::string(to_string(c.law)) + " at " + where];
      }
  if (counts.empty()) return;
  std::vector<std::pair<int, std::string>> sorted;
  for (const auto& [where, n] : counts) sorted.push_back({n, where});
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  md << "\nWhere (law and directions, azimuths pooled): ";
  for (std::size_t k = 0; k < sorted.size() && k < 12; ++k)
    md << (k ? "; " : "") << sorted[k].second << ": " << sorted[k].first;
  if (sorted.size() > 12) md << "; " << sorted.size() - 12 << " more places";
  md << ".\n";
}

void refused_list(std::ostringstream& md, const std::vector<ExtremesRow>& rows) {
  std::vector<std::string> refused;
  for (const auto& r : rows) refused.insert(refused.end(), r.refused.begin(), r.refused.end());
  if (refused.empty()) return;
  md << "\n### Specs the parser refused\n\nA parameter at an end of its own range can break a joint "
        "constraint (kd + ks <= 1, ...); these are left out of the grid, as a user could not ask for them "
        "either.\n\n";
  for (const auto& text : refused) md << "- `" << text << "`\n";
}

/// A CSV field: quoted when it holds a comma or a quote (doubled).
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"") == std::string::npos) return text;
  std::string out = "\"";
  for (char ch : text) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

}  // namespace

std::string extremes_csv(const std::vector<ExtremesRow>& rows, const std::string& command) {
  std::ostringstream csv;
  csv << "# generated by `" << command << "`; do not edit by hand\n"
      << "spec,law,where,value,estimate,evaluations,converged,reference,reference_error,reference_rule,"
         "second_reference,second_reference_error,verdict\n";
  for (const auto& r : rows)
    for (const ExtremesCase& c : r.all) {
      const bool judged = c.finite && c.converged && c.law != Law::f;
      const bool second = c.dishonest || c.references_disagree;
      csv << csv_field(c.spec) << "," << to_string(c.law) << "," << csv_field(c.where) << ","
          << number(c.engine.value, 15) << "," << number(c.engine.error, 3) << "," << c.engine.evaluations << ","
          << (c.converged ? 1 : 0) << ","
          << (judged ? number(c.reference, 15) + "," + number(c.reference_error, 3) + "," + csv_field(c.reference_rule)
                     : ",,")
          << "," << (second ? number(c.second_reference, 15) + "," + number(c.second_reference_error, 3) : ",") << ","
          << (c.law == Law::f ? (c.finite ? "finite" : "non-finite") : verdict(c)) << "\n";
    }
  return csv.str();
}

std::string extremes_markdown(const std::vector<ExtremesRow>& rows, const ExtremesOptions& options,
                              const std::string& command, double seconds, const std::string& csv_file, bool resumed) {
  std::ostringstream md;
  md << "## Extremes grid: every model at its extremes\n\n"
     << "Generated by `" << command << "` (do not edit by hand); the run took " << number(seconds)
     << " s of wall time on " << tbb_threads() << " threads"
     << (resumed ? " (summed over the runs that measured its models)" : "")
     << (csv_file.empty() ? std::string(".")
                          : "; every case, judged or not, is in [" + csv_file + "](" + csv_file + ").")
     << "\n\n"
     << (options.defaults_only || options.quick
             ? "Every registered model at its defaults only (this run leaves out the parameters' ends), with "
               "anisotropic radii and mixtures; "
             : "Every registered model at its defaults, with each parameter at either end of its documented range "
               "(exponents capped at " +
                   number(kExtremesExponentCap) + "), anisotropic radii and mixtures; ")
     << (options.quick ? "this run is the quick slice (the grid's corners); " : "")
     << "the laws f, g, h, a at i·n ∈ {−1, −0.999, 0, 1e-9, 1e-6, 1}, "
        "j·n ∈ {0, 1e-9, 1e-6, 1} (the halfway-vector-disk models also at 1e-4 and θ_o = 89.99°), "
        "φ ∈ {0°, 90°, 180°} (h: j only; a: i·n ≥ 0; repeats that an isotropic model cannot tell apart are run "
        "once). The engine runs at an absolute tolerance of "
     << number(options.engine_tolerance)
     << ". Each converged result is judged against an independent reference (reference/, written apart from "
        "integrate/: nested on the lune, to 1e-10 of the value or a tenth of the engine's tolerance, whichever is "
        "looser, break points at the model's peaks and hints, the hemisphere's coordinate pole turned away from a "
        "grazing lobe), the first of "
        "three that is resolved: Boost gauss_kronrod<61> within "
     << number(double(kExtremesReferenceBudget))
     << " evaluations; gauss_kronrod<31> with the nesting swapped, within as many; Boost's tanh_sinh at both "
        "levels, whose nodes crowd towards the horizon and the lune's tips, within "
     << number(double(kExtremesTanhSinhBudget))
     << ". A fourth, tanh_sinh at both levels in polar coordinates about the antipode of the fixed direction "
        "(where a microfacet model's integrand grows as 1/|k + fixed|, a point 1e-9 below the horizon when the view "
        "is 1e-9 above it, and tanh_sinh on the lune is up to 1e-7 off), within "
     << number(double(kExtremesAntipodeBudget))
     << ", is a witness, never a judge alone: it is asked where the engine disagrees with the judge, and where "
        "none of the three is resolved it is one of the unresolved bounds (one of a refuting pair, never alone); it "
        "is itself confidently 4e-8 off on hvd-empirical's ridge along the edge of a lune. A reference is resolved "
        "when its stated error is within "
        "the engine's tolerance, times |value| where "
        "that exceeds 1: the references state about 1e-10 of the value at best, so a value of 1e5 is judged to "
        "1e-3 absolute, not 1e-8 (the cases judged so are counted below). *Dishonest*: "
        "|engine − reference| exceeds the engine's estimate plus the reference's error, and no other resolved "
        "reference agrees with the engine; where one does, the case counts as *references disagree* instead, and "
        "is listed. Where none of the three is resolved, two whose own bounds still exclude the engine's value and "
        "agree "
        "with each other prove it dishonest all the same (an unresolved bound alone can be wrong, and two that "
        "exclude each other are no more than one); a refuter without such a partner makes the case *references "
        "disagree* where another agrees with the engine and excludes it; otherwise the case is *reference "
        "unresolved*: not judged, counted and listed. f is the formula itself (error 0): only its finiteness is "
        "judged. Measured models (merl, "
        "tabulated) need a data file and are not in this grid.\n\n"
     << "| model | specs | cases | non-finite | not converged | dishonest | references disagree | reference unresolved "
        "| "
        "judged by a fallback | seconds (summed over cases) |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  ExtremesRow total;
  total.model = "**total**";
  int judged_laws = 0, judged_at_scale = 0;
  for (const auto& r : rows) {
    md << "| " << r.model << " | " << r.specs << " | " << r.cases << " | " << r.non_finite << " | " << r.not_converged
       << " | " << r.dishonest << " | " << r.references_disagree << " | " << r.unresolved << " | "
       << r.judged_by_fallback << " | " << number(r.seconds) << " |\n";
    total.specs += r.specs, total.cases += r.cases, total.non_finite += r.non_finite;
    total.not_converged += r.not_converged, total.dishonest += r.dishonest;
    total.references_disagree += r.references_disagree, total.unresolved += r.unresolved;
    total.judged_by_fallback += r.judged_by_fallback;
    total.seconds += r.seconds;
    for (const ExtremesCase& c : r.all) {
      judged_laws += c.law != Law::f;
      judged_at_scale += judged(c) && c.reference_error > options.engine_tolerance;
    }
  }
  const double unjudged = judged_laws ? double(total.unresolved) / judged_laws : 0.0;
  md << "| " << total.model << " | " << total.specs << " | " << total.cases << " | " << total.non_finite << " | "
     << total.not_converged << " | " << total.dishonest << " | " << total.references_disagree << " | "
     << total.unresolved << " | " << total.judged_by_fallback << " | " << number(total.seconds) << " |\n\n"
     << "- 0 non-finite results: **" << (total.non_finite == 0 ? "met" : "missed") << "** (" << total.non_finite
     << " of " << total.cases << ").\n"
     << "- 0 dishonest results: **" << (total.dishonest == 0 ? "met" : "missed") << "** (" << total.dishonest << " of "
     << total.cases << "; " << total.references_disagree << " more where the references disagree).\n"
     << "- Unjudged (reference unresolved) ≤ 1% of the cases of g, h and a: **" << (unjudged <= 0.01 ? "met" : "missed")
     << "** (" << total.unresolved << " of " << judged_laws << ", " << number(100 * unjudged, 3) << "%).\n"
     << "- Not converged (the engine says so; not judged): " << total.not_converged << " of " << judged_laws << ".\n"
     << "- Judged at the value's scale (the reference's error above " << number(options.engine_tolerance)
     << " but within " << number(options.engine_tolerance) << " × |value|): " << judged_at_scale << " of "
     << judged_laws << ".\n";
  auto by_excess = [](const ExtremesCase& a, const ExtremesCase& b) {
    auto excess = [](const ExtremesCase& c) {
      return std::abs(c.engine.value - c.reference) / (c.engine.error + c.reference_error);
    };
    return excess(a) > excess(b);
  };
  auto by_estimate = [](const ExtremesCase& a, const ExtremesCase& b) { return a.engine.error > b.engine.error; };
  auto by_reference_error = [](const ExtremesCase& a, const ExtremesCase& b) {
    return a.reference_error > b.reference_error;
  };
  flagged_kind(md, rows, "non-finite", "Non-finite results", by_estimate);
  flagged_kind(md, rows, "dishonest", "Dishonest results", by_excess);
  flagged_kind(md, rows, "references disagree", "Where the references disagree", by_excess);
  flagged_kind(md, rows, "not converged", "Not converged, largest estimates first", by_estimate);
  where_counts(md, rows, "not converged");
  flagged_kind(md, rows, "reference unresolved", "Reference unresolved, largest reference errors first",
               by_reference_error);
  where_counts(md, rows, "reference unresolved");
  refused_list(md, rows);
  return md.str();
}

}  // namespace ganzfeld
