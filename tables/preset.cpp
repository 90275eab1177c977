#include "tables/preset.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>

#include <tbb/parallel_for.h>

#include "integrate/laws.h"
#include "models/charlie.h"
#include "models/ggx.h"
#include "models/registry.h"
#include "models/spec.h"
#include "tables/bake.h"
#include "util/error.h"
#include "util/names.h"

namespace ganzfeld::tables {

namespace {
constexpr std::array kPresets{util::EnumName<Preset>{Preset::dfg, "dfg"},
                              util::EnumName<Preset>{Preset::kulla_conty, "kulla-conty"}};
constexpr std::array kDfgLayouts{util::EnumName<DfgLayout>{DfgLayout::filament, "filament"},
                                 util::EnumName<DfgLayout>{DfgLayout::ue4, "ue4"}};
}  // namespace

const char* to_string(Preset preset) { return util::name_of(kPresets, preset); }
Preset parse_preset(const std::string& text) { return util::parse_name(kPresets, "preset", text); }

const char* to_string(DfgLayout layout) { return util::name_of(kDfgLayouts, layout); }
DfgLayout parse_dfg_layout(const std::string& text) { return util::parse_name(kDfgLayouts, "DFG layout", text); }

std::string preset_family(const Model& model, const PresetOptions& options) {
  const auto* ggx = dynamic_cast<const Ggx*>(&model);
  const Named preset{"preset", to_string(options.preset)};
  if (!ggx) {
    const std::string spec = model.spec();
    const Spec parsed = parse_spec(spec);
    bool has_axis = false;  // a mixture has no parameters of its own
    if (!parsed.is_mixture())
      for (const ParamInfo& p : find_model(parsed.terms.front().model.name).parameters)
        has_axis = has_axis || p.name == options.axis;
    if (!has_axis)
      throw InputError(
          {preset, " needs a ggx model: '" + spec + "' has no parameter " + options.axis + " for the table's axis"});
    throw InputError(
        {preset, " is defined for ggx (its channels are GGX and Charlie albedos), not for '" + spec + "'"});
  }
  if (!model.traits().isotropic)
    throw InputError({preset, " needs an isotropic ggx model, not '" + model.spec() + "'"});
  return spec_text({"ggx", {{"g2", ggx->parameters().at("g2")}}});
}

std::vector<int> parse_preset_resolution(const std::string& text) {
  const InputError bad({Named{"res", "'" + text + "'"},
                        " is not a preset resolution; expected N or NPxNMU (parameter x "
                        "cos_theta_i samples) with integers from 2 to 4096"});
  std::vector<int> counts;
  try {  // each part is a one-axis resolution "N"
    const std::size_t x = text.find('x');
    counts.push_back(parse_resolution(text.substr(0, x), Law::a).front());
    counts.push_back(x == std::string::npos ? counts[0] : parse_resolution(text.substr(x + 1), Law::a).front());
  } catch (const InputError&) { throw bad; }
  if (std::max(counts[0], counts[1]) > 4096) throw bad;
  return counts;
}

namespace {

/// The integrals a preset's channels are made of, per texel (α, μ).
enum class Base { fc, e, charlie, e_avg };

/// The integral `base` at (α > 0, μ), or its exact α → 0 limit (preset.h) at α = 0.
Estimate integral(Base base, double alpha, double mu, ggx::G2Form g2, const CubatureOptions& c) {
  if (alpha == 0.0) {
    const double mirror_fc = std::pow(1.0 - mu, 5);
    return {base == Base::fc ? mirror_fc : base == Base::charlie ? 0.0 : 1.0, 0.0, 0, true};
  }
  const Vec3 i = direction_from_cos(mu);
  switch (base) {
    case Base::fc: return albedo(Ggx({alpha, alpha}, 0.0, g2), i, c);
    case Base::e: return albedo(Ggx({alpha, alpha}, 1.0, g2), i, c);
    case Base::charlie: return albedo(Charlie(alpha), i, c);
    case Base::e_avg: return double_diffuse(Ggx({alpha, alpha}, 1.0, g2), c);
  }
  return {};
}

/// A channel as a sum of base integrals with signs: value = Σ sign·base, error = Σ |errors|.
struct ChannelRecipe {
  const char* name;
  const char* definition;
  std::vector<std::pair<Base, double>> terms;
};

std::vector<ChannelRecipe> recipes(const PresetOptions& options) {
  constexpr const char* kFc = "integral of f1 (1 - v.h)^5 cos (ggx:f0=0 albedo; f1: ggx with F = 1)";
  constexpr const char* kE = "integral of f1 cos (ggx:f0=1 albedo, E(mu, alpha))";
  if (options.preset == Preset::kulla_conty)
    return {{"e", kE, {{Base::e, 1.0}}},
            {"e_avg",
             "E_avg(alpha) = 2 integral of E(mu) mu dmu (law r of ggx:f0=1), constant along mu",
             {{Base::e_avg, 1.0}}}};
  if (options.layout == DfgLayout::ue4)
    return {{"scale", "integral of f1 (1 - (1 - v.h)^5) cos (Unreal's scale)", {{Base::e, 1.0}, {Base::fc, -1.0}}},
            {"bias", "integral of f1 (1 - v.h)^5 cos (Unreal's bias)", {{Base::fc, 1.0}}}};
  return {
      {"dfg_fc", kFc, {{Base::fc, 1.0}}},
      {"dfg_e", kE, {{Base::e, 1.0}}},
      {"charlie", "integral of f cos of charlie:alpha=alpha (Neubelt-Pettineo visibility)", {{Base::charlie, 1.0}}}};
}

void check_options(const PresetOptions& options) {
  if (options.axis != kAxisRoughness && options.axis != kAxisAlpha)
    throw InputError("parameter axis '" + options.axis + "' is not allowed; allowed: roughness, alpha");
  if (options.resolution.size() != 2 || std::min(options.resolution[0], options.resolution[1]) < 2)
    throw InputError("a preset table needs 2 axes of at least 2 samples each");
  if (!std::isfinite(options.tolerance) || !(options.tolerance > 0.0))
    throw InputError("tolerance " + format_number(options.tolerance) + " is not allowed; expected a positive number");
  if (options.encoding == Encoding::unorm16)
    throw InputError("encoding unorm16 is for law tables (bake); a preset table allows: half, float");
}

}  // namespace

namespace {

/// One base integral to compute: at (alpha, mu), stored at `slot` of its base's results.
struct Task {
  Base base;
  double alpha, mu;
  std::size_t slot;
};

/// The tasks' integrals, in parallel (independent integrals, so the bits do not depend on the
/// thread count), with one progress count shared by every phase of the bake.
class Integrator {
 public:
  Integrator(ggx::G2Form g2, const PresetOptions& options, std::uint64_t total)
      : g2_(g2), options_(options), total_(total) {}

  std::map<Base, std::vector<Estimate>> run(const std::vector<Task>& tasks, const CubatureOptions& cubature) {
    std::map<Base, std::vector<Estimate>> out;
    for (const Task& t : tasks) out[t.base].resize(std::max(out[t.base].size(), t.slot + 1));
    tbb::parallel_for(std::size_t{0}, tasks.size(), [&](std::size_t w) {
      const Task& t = tasks[w];
      out.at(t.base)[t.slot] = integral(t.base, t.alpha, t.mu, g2_, cubature);
      const std::uint64_t d = ++done_;
      if (options_.progress && (d % 64 == 0 || d == total_)) {
        std::lock_guard lock(progress_mutex_);
        options_.progress(d, total_);
      }
    });
    return out;
  }

 private:
  ggx::G2Form g2_;
  const PresetOptions& options_;
  std::uint64_t total_;
  std::atomic<std::uint64_t> done_{0};
  std::mutex progress_mutex_;
};

/// The distinct bases of the channels.
std::vector<Base> bases_of(const std::vector<ChannelRecipe>& channel_recipes) {
  std::vector<Base> bases;
  for (const ChannelRecipe& r : channel_recipes)
    for (const auto& [base, sign] : r.terms)
      if (std::find(bases.begin(), bases.end(), base) == bases.end()) bases.push_back(base);
  return bases;
}

/// A channel's value and error bound at slot m from its bases' estimates (e_avg: at slot
/// m_avg, it depends on the parameter only); `converged` is cleared when one term is not.
std::pair<double, double> combine(const ChannelRecipe& r, const std::map<Base, std::vector<Estimate>>& estimates,
                                  std::size_t m, std::size_t m_avg, bool& converged) {
  double value = 0.0, error = 0.0;
  for (const auto& [base, sign] : r.terms) {
    const Estimate& e = estimates.at(base)[base == Base::e_avg ? m_avg : m];
    value += sign * e.value;
    error += e.error;
    converged = converged && e.converged;
  }
  return {value, error};
}

/// Tasks for every base at every texel (e_avg once per row, at the row's first slot).
std::vector<Task> texel_tasks(const ParamTable& table, const std::vector<Base>& bases, const std::string& axis) {
  const int n_mu = table.axes[1].count;
  std::vector<Task> tasks;
  for (Base b : bases)
    for (std::size_t m = 0; m < table.entries(); ++m)
      if (b != Base::e_avg || m % n_mu == 0)
        tasks.push_back({b, alpha_of(axis, grid_coordinate(table.axes[0], table.grid, static_cast<int>(m / n_mu))),
                         grid_coordinate(table.axes[1], table.grid, static_cast<int>(m % n_mu)), m});
  return tasks;
}

/// Whether validation point m is the first of its parameter value (the points come sorted by
/// parameter): e_avg depends on the parameter only, so it is integrated there once and every
/// later point of that parameter reads it from there.
bool starts_parameter(const std::vector<std::pair<double, double>>& points, std::size_t m) {
  return m == 0 || points[m].first != points[m - 1].first;
}

/// Tasks for every base at every validation point (e_avg once per distinct parameter, at the
/// slot of its first point).
std::vector<Task> validation_tasks(const std::vector<std::pair<double, double>>& points, const std::vector<Base>& bases,
                                   const std::string& axis) {
  std::vector<Task> tasks;
  for (Base b : bases)
    for (std::size_t m = 0; m < points.size(); ++m)
      if (b != Base::e_avg || starts_parameter(points, m))
        tasks.push_back({b, alpha_of(axis, points[m].first), points[m].second, m});
  return tasks;
}

/// Sets each channel's lookup_error (param_table.h) from direct cubature at the validation
/// points, at kValidationToleranceRatio x the bake's tolerance: the interpolation error it
/// measures is orders above that (docs/realtime.md).
void validate_lookup(ParamTable& table, const std::vector<ChannelRecipe>& channel_recipes,
                     const std::vector<std::pair<double, double>>& points,
                     const std::map<Base, std::vector<Estimate>>& estimates) {
  for (std::size_t c = 0; c < table.channels.size(); ++c) {
    Channel& ch = table.channels[c];
    double measured = 0.0;
    const double max_texel = ch.node_error();
    std::size_t m_avg = 0;
    for (std::size_t m = 0; m < points.size(); ++m) {
      if (starts_parameter(points, m)) m_avg = m;
      bool converged = true;
      const auto [value, error] = combine(channel_recipes[c], estimates, m, m_avg, converged);
      if (!std::isfinite(value) || !std::isfinite(error))
        throw InputError(std::string("channel ") + ch.name + " is not finite at validation point " + std::to_string(m) +
                         " (the cubature met a non-finite integrand); nothing written");
      const double lookup = sample_param(table, c, points[m].first, points[m].second).value;
      measured = std::max(measured, std::abs(lookup - value) + error);
    }
    ch.lookup_error = std::max(kLookupMargin * measured, max_texel);
    table.lookup_error = std::max(table.lookup_error, ch.lookup_error);
  }
  table.lookup_checks = static_cast<long long>(points.size());
}

}  // namespace

ParamTable bake_preset(const Model& model, const PresetOptions& options) {
  check_options(options);
  ParamTable table;
  table.model = preset_family(model, options);  // refuses all but isotropic ggx
  const auto g2 = static_cast<ggx::G2Form>(static_cast<int>(dynamic_cast<const Ggx&>(model).parameters().at("g2")));
  table.preset = to_string(options.preset);
  table.layout = options.preset == Preset::dfg ? to_string(options.layout) : "kulla-conty";
  table.axes = {{options.axis, 0.0, 1.0, options.resolution[0], Mapping::linear},
                {kAxisCosThetaI, 0.0, 1.0, options.resolution[1], Mapping::linear}};
  table.grid = options.grid;
  table.tolerance = options.tolerance;
  table.encoding = options.encoding;
  table.version = GANZFELD_VERSION;
  const std::vector<ChannelRecipe> channel_recipes = recipes(options);
  const std::vector<Base> bases = bases_of(channel_recipes);
  const std::vector<Task> texels = texel_tasks(table, bases, options.axis);
  const std::vector<std::pair<double, double>> points = param_validation_points(table);
  const std::vector<Task> checks = validation_tasks(points, bases, options.axis);

  CubatureOptions cubature;
  cubature.abs_tol = options.tolerance;
  cubature.max_evaluations = options.max_evaluations;
  CubatureOptions check_cubature = cubature;
  check_cubature.abs_tol *= kValidationToleranceRatio;
  Integrator integrator(g2, options, texels.size() + checks.size());
  const std::map<Base, std::vector<Estimate>> grid = integrator.run(texels, cubature);

  const int n_mu = options.resolution[1];
  for (const ChannelRecipe& r : channel_recipes) {
    const std::size_t n = table.entries();
    Channel ch{r.name, r.definition, std::vector<float>(n), std::vector<float>(n), 0};
    for (std::size_t m = 0; m < n; ++m) {
      bool converged = true;
      const auto [value, error] = combine(r, grid, m, m - m % n_mu, converged);
      if (!std::isfinite(value) || !std::isfinite(error))
        throw InputError(std::string("channel ") + r.name + " is not finite at entry " + std::to_string(m) +
                         " (the cubature met a non-finite integrand); nothing written");
      ch.value[m] = round_to_encoding(value, options.encoding);
      ch.error[m] = round_up_to_encoding(error + std::abs(value - static_cast<double>(ch.value[m])), options.encoding);
      ch.unconverged += !converged;
      table.node_error = std::max(table.node_error, static_cast<double>(ch.error[m]));
    }
    table.channels.push_back(std::move(ch));
  }
  validate_lookup(table, channel_recipes, points, integrator.run(checks, check_cubature));
  return table;
}

}  // namespace ganzfeld::tables
