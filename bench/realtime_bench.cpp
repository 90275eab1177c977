#include "bench/realtime_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <vector>

#include <tbb/parallel_for.h>
#include <boost/math/quadrature/gauss.hpp>

#include "bench/cubature_bench.h"
#include "integrate/laws.h"
#include "models/ggx_energy.h"
#include "models/ggx_ms.h"
#include "models/spec.h"
#include "tables/param_table.h"
#include "tables/preset.h"
#include "util/timing.h"

namespace ganzfeld::bench {

namespace {

using tables::ParamTable;

// The targets of docs/realtime.md ("Accuracy").
constexpr double kTexelTarget = 1e-6;  // per-texel error bound, for alpha >= kMinAlpha
constexpr double kMinAlpha = 1e-3;
constexpr double kBakeSecondsTarget = 10.0;  // a 64x64 table on 2 cores
constexpr double kFurnaceTarget = 1e-5;      // |a - 1| of ggx-ms with f0 = 1
constexpr double kFurnaceTol = 1e-9;         // the cubature's tolerance for the furnace albedos
constexpr int kCompared = 11;                // rows and columns compared with the reference: 121 texels

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}
const char* verdict(bool ok) { return ok ? "**met**" : "**missed**"; }

double alpha_at(const ParamTable& t, int row) {
  return tables::alpha_of(t.axes[0].name, tables::grid_coordinate(t.axes[0], t.grid, row));
}
double mu_at(const ParamTable& t, int k) { return tables::grid_coordinate(t.axes[1], t.grid, k); }

struct Timed {
  ParamTable table;
  std::vector<double> seconds;
};

Timed bake_timed(tables::Preset preset, int n, int repeats) {
  tables::PresetOptions o;
  o.preset = preset;
  o.resolution = {n, n};
  const ModelPtr ggx = parse_model("ggx");
  Timed t;
  t.seconds = util::time_runs(repeats, [&] { t.table = tables::bake_preset(*ggx, o); });
  return t;
}

void error_section(std::ostringstream& md, const std::vector<const Timed*>& bakes) {
  md << "## Per-texel error bound\n\nEvery texel's stored bound (the cubature's error estimate + float "
        "rounding, rounded up, no margin; checked against an independent estimator below), "
        "the largest over the texels with α ≥ 1e-3 and over all texels; target ≤ 1e-6 for α ≥ 1e-3.\n\n"
        "| preset | channel | max bound, α ≥ 1e-3 | max bound, all texels | unconverged | target |\n"
        "|---|---|---|---|---|---|\n";
  for (const Timed* b : bakes) {
    const ParamTable& t = b->table;
    const int n_mu = t.axes[1].count;
    for (const tables::Channel& ch : t.channels) {
      double above = 0.0, all = 0.0;
      for (std::size_t m = 0; m < ch.error.size(); ++m) {
        all = std::max(all, static_cast<double>(ch.error[m]));
        if (alpha_at(t, static_cast<int>(m / n_mu)) >= kMinAlpha)
          above = std::max(above, static_cast<double>(ch.error[m]));
      }
      md << "| " << t.preset << " | `" << ch.name << "` | " << num(above) << " | " << num(all) << " | "
         << ch.unconverged << " | " << verdict(above <= kTexelTarget) << " |\n";
    }
  }
}

void timing_section(std::ostringstream& md, const std::vector<const Timed*>& bakes) {
  md << "\n## Bake time\n\n`bake_preset` of the whole table with the default options (tolerance "
     << num(tables::kPresetTolerance)
     << ", texel grid), on the machine below with every hardware thread; target ≤ 10 s for 64x64 on 2 cores.\n\n"
        "| preset | samples | runs | median (s) | min … max (s) | target |\n|---|---|---|---|---|---|\n";
  for (const Timed* b : bakes) {
    const auto [lo, hi] = std::minmax_element(b->seconds.begin(), b->seconds.end());
    const double median = util::median(b->seconds);
    md << "| " << b->table.preset << " | " << b->table.axes[0].count << "x" << b->table.axes[1].count << " | "
       << b->seconds.size() << " | " << num(median) << " | " << num(*lo) << " … " << num(*hi) << " | "
       << verdict(median <= kBakeSecondsTarget) << " |\n";
  }
  md << "\nMachine: " << util::machine_description() << ". The timings share it with whatever else runs there.\n";
}

void furnace_section(std::ostringstream& md, const RealtimeOptions& options) {
  const std::vector<double> alphas =
      options.quick ? std::vector<double>{1.0, 0.25} : std::vector<double>{1.0, 0.5, 0.25, 0.1};
  const std::vector<double> mus{0.05, 0.2, 0.4, 0.6, 0.8, 1.0};
  md << "\n## White furnace: ggx-ms against plain GGX\n\nAlbedo a(μ) with f0 = 1 by the cubature (tolerance 1e-9) at "
        "μ ∈ {0.05, 0.2, 0.4, 0.6, 0.8, 1}: ggx-ms should give 1 (target |a − 1| ≤ 1e-5); plain ggx gives E(μ), "
        "losing 1 − E. Its E table (models/ggx_ms.h) comes from models/ggx_energy's rule, so each row is two "
        "integrators agreeing.\n\n"
        "| α | ggx-ms max \\|a − 1\\| | its E table's error | ggx: max loss 1 − E(μ) | ggx: 1 − E_avg | target |\n"
        "|---|---|---|---|---|---|\n";
  for (double alpha : alphas) {
    const ModelPtr ms = parse_model("ggx-ms:alpha=" + num(alpha)), plain = parse_model("ggx:alpha=" + num(alpha));
    const ggx::EnergyTable& e = dynamic_cast<const GgxMs&>(*ms).energy();
    double deviation = 0.0, loss = 0.0;
    for (double mu : mus) {
      const Estimate a = albedo(*ms, direction_from_cos(mu), {kFurnaceTol});
      deviation = std::max(deviation, std::abs(a.value - 1.0) + a.error);
      loss = std::max(loss, 1.0 - albedo(*plain, direction_from_cos(mu), {kFurnaceTol}).value);
    }
    md << "| " << num(alpha) << " | " << num(deviation) << " | " << num(e.error) << " | " << num(loss) << " | "
       << num(1.0 - e.E_avg) << " | " << verdict(deviation <= kFurnaceTarget) << " |\n";
  }
}

/// |table − reference| at kCompared x kCompared texels of a channel, against table + reference errors.
struct Comparison {
  int texels = 0, within = 0;  ///< compared, and within the table's bound + the reference's error
  double max_difference = 0.0, max_ratio = 0.0, max_reference_error = 0.0;
};

template <typename Reference>
Comparison compare(const ParamTable& t, const std::string& channel, Reference reference) {
  const tables::Channel& ch = t.channels[t.channel_index(channel)];
  const int n_p = t.axes[0].count, n_mu = t.axes[1].count;
  std::vector<std::pair<int, int>> texels;
  for (int a = 0; a < kCompared; ++a)
    for (int b = 0; b < kCompared; ++b)
      texels.push_back({a * (n_p - 1) / (kCompared - 1), b * (n_mu - 1) / (kCompared - 1)});
  std::vector<ggx::ReferenceValue> refs(texels.size());
  tbb::parallel_for(std::size_t{0}, texels.size(), [&](std::size_t k) {
    refs[k] = reference(mu_at(t, texels[k].second), alpha_at(t, texels[k].first), texels[k].first);
  });
  Comparison c;
  for (std::size_t k = 0; k < texels.size(); ++k) {
    const std::size_t m = static_cast<std::size_t>(texels[k].first) * n_mu + texels[k].second;
    const double d = std::abs(ch.value[m] - refs[k].value);
    c.max_difference = std::max(c.max_difference, d);
    c.max_ratio = std::max(c.max_ratio, d / (ch.error[m] + refs[k].error));
    c.within += d <= ch.error[m] + refs[k].error;
    c.max_reference_error = std::max(c.max_reference_error, refs[k].error);
    ++c.texels;
  }
  return c;
}

/// E_avg = 2 ∫ E μ dμ by Gauss–Legendre over the reference E, on panels graded towards μ = 0.
ggx::ReferenceValue e_avg_reference(double alpha) {
  const double cuts[] = {0.0, 1e-3, 0.01, 0.03, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0};
  ggx::ReferenceValue sum;
  for (int p = 0; p + 1 < 10; ++p) {
    std::vector<ggx::ReferenceValue> at;
    const double value = boost::math::quadrature::gauss<double, 7>::integrate(
        [&](double mu) {
          at.push_back(ggx::ggx_albedo_reference(mu, alpha, 1.0, false));
          return 2.0 * mu * at.back().value;
        },
        cuts[p], cuts[p + 1]);
    sum.value += value;
    for (const auto& r : at) sum.error = std::max(sum.error, r.error);  // ∫ 2μ dμ = 1 carries the largest
  }
  return sum;
}

void comparison_section(std::ostringstream& md, const ParamTable& dfg, const ParamTable& kc) {
  md << "\n## Against an independent estimator\n\nThe reference is models/ggx_energy.h: a tensor Gauss–Legendre rule "
        "(Boost.Math's 20 points) over the half vector (θ_h, φ_h), the horizon cut exactly at θ* = δ/2 + π/4, panels "
        "graded towards the lobe and the horizon crossing, D and Smith Λ written out again: no code of integrate/ or "
        "models/ggx. Its error is |level 1 − level 2| (twice the panels). A texel agrees when |table − reference| ≤ "
        "the table's bound + the reference's error; `ratio` is the largest |table − reference| / (that sum).\n\n"
        "| channel | texels | max \\|table − reference\\| | max ratio | max reference error | all within bounds |\n"
        "|---|---|---|---|---|---|\n";
  int texels = 0, within = 0;
  auto row = [&](const std::string& name, const Comparison& c) {
    texels += c.texels, within += c.within;
    md << "| `" << name << "` | " << c.texels << " | " << num(c.max_difference) << " | " << num(c.max_ratio) << " | "
       << num(c.max_reference_error) << " | " << verdict(c.max_ratio <= 1.0) << " |\n";
  };
  row("dfg_fc",
      compare(dfg, "dfg_fc", [](double mu, double a, int) { return ggx::ggx_albedo_reference(mu, a, 0.0, false); }));
  row("dfg_e",
      compare(dfg, "dfg_e", [](double mu, double a, int) { return ggx::ggx_albedo_reference(mu, a, 1.0, false); }));
  row("charlie",
      compare(dfg, "charlie", [](double mu, double a, int) { return ggx::charlie_albedo_reference(mu, a); }));
  row("e", compare(kc, "e", [](double mu, double a, int) { return ggx::ggx_albedo_reference(mu, a, 1.0, false); }));
  // E_avg once per compared row (constant along μ), in parallel, then read by every texel of the row.
  std::vector<ggx::ReferenceValue> avg(kc.axes[0].count);
  tbb::parallel_for(0, kCompared, [&](int a) {
    const int r = a * (kc.axes[0].count - 1) / (kCompared - 1);
    avg[r] = e_avg_reference(alpha_at(kc, r));
  });
  row("e_avg", compare(kc, "e_avg", [&](double, double, int r) { return avg[r]; }));
  md << "\n- No margin: each texel's bound is the cubature's own estimate + float rounding (tables/preset.cpp), "
        "and the compared texels within it: "
     << verdict(within == texels) << " (" << within << " of " << texels << ", " << num(100.0 * within / texels)
     << "%; target 100%).\n";
  md << "\n(`e_avg`'s reference integrates the reference E over μ by 7-point Gauss–Legendre on 9 panels graded "
        "towards μ = 0; its error column is the largest error of the E values it used, not that quadrature's.)\n";
}

}  // namespace

/// What a shader reads between the texels: each channel's validated lookup error (bilinear,
/// ParamTable::lookup_error) and how often it holds at fresh seeded points against the
/// independent reference, for the DFG table.
void lookup_section(std::ostringstream& md, const std::vector<const Timed*>& bakes, int fresh_points) {
  md << "\n## Between the texels: the bilinear lookup error\n\nA shader reads the table with bilinear "
        "filtering; between the texels the error is interpolation, not cubature. Each channel's `lookup error` is "
        "the table's headline (`ganzfeld info`): "
     << num(tables::kLookupMargin)
     << " × the largest |lookup − cubature| + cubature error at the points between the samples and on the "
        "edges, over α ≥ "
     << num(tables::kMinValidatedAlpha) << " and μ ≥ " << num(tables::kMinValidatedMu)
     << " (below, the albedos of small α drop to 0 in a layer about α wide that no bilinear table of this size "
        "resolves). `holds` is the fraction of "
     << fresh_points
     << " seeded random points (roughness, μ) in that domain where |lookup − independent reference| ≤ lookup "
        "error + the reference's error (models/ggx_energy.h, as below).\n\n"
        "| preset | channel | lookup error | per-texel bound | max \\|lookup − reference\\| | holds |\n"
        "|---|---|---|---|---|---|\n";
  for (const Timed* b : bakes) {
    const ParamTable& t = b->table;
    for (std::size_t c = 0; c < t.channels.size(); ++c) {
      const tables::Channel& ch = t.channels[c];
      std::string actual = "–", holds = "–";
      const bool referenced = ch.name == "dfg_fc" || ch.name == "dfg_e" || ch.name == "charlie" || ch.name == "e";
      if (referenced && fresh_points > 0) {
        std::vector<double> diff(fresh_points), slack(fresh_points);
        tbb::parallel_for(0, fresh_points, [&](int p) {
          // Seeded by the point's index: the same points in every run, whatever the thread count.
          std::mt19937_64 rng(20261125u + static_cast<unsigned>(p));
          std::uniform_real_distribution<double> unit(0.0, 1.0);
          const double r_min = std::sqrt(tables::kMinValidatedAlpha);
          const double r = r_min + (1.0 - r_min) * unit(rng);
          const double mu = tables::kMinValidatedMu + (1.0 - tables::kMinValidatedMu) * unit(rng);
          const double x = t.axes[0].name == tables::kAxisRoughness ? r : r * r, alpha = r * r;
          const ggx::ReferenceValue ref =
              ch.name == "charlie" ? ggx::charlie_albedo_reference(mu, alpha)
                                   : ggx::ggx_albedo_reference(mu, alpha, ch.name == "dfg_fc" ? 0.0 : 1.0, false);
          diff[p] = std::abs(tables::sample_param(t, c, x, mu).value - ref.value);
          slack[p] = ch.lookup_error + ref.error - diff[p];
        });
        actual = num(*std::max_element(diff.begin(), diff.end()));
        const auto held = std::count_if(slack.begin(), slack.end(), [](double s) { return s >= 0.0; });
        holds = num(100.0 * held / fresh_points) + "%";
      }
      md << "| " << t.preset << " | `" << ch.name << "` | " << num(ch.lookup_error) << " | " << num(ch.node_error())
         << " | " << actual << " | " << holds << " |\n";
    }
  }
}

std::string realtime_markdown(const RealtimeOptions& options, const std::string& command) {
  const int n = options.quick ? 16 : 64, repeats = options.quick ? 1 : std::max(1, options.repeats);
  const Timed dfg = bake_timed(tables::Preset::dfg, n, repeats);
  const Timed kc = bake_timed(tables::Preset::kulla_conty, n, repeats);
  std::ostringstream md;
  md << "# The real-time tables: accuracy and speed\n\n<!-- generated by `" << command
     << "`; do not edit -->\n\nGenerated by `" << command << "`. The DFG (`bake preset dfg --model ggx`, Filament's "
     << "channels) and Kulla–Conty (`bake preset kulla-conty --model ggx`) tables at " << n << "x" << n
     << " texel-centred samples over (roughness, μ), their format in docs/lut-format.md (version 3).\n\n";
  error_section(md, {&dfg, &kc});
  timing_section(md, {&dfg, &kc});
  lookup_section(md, {&dfg, &kc}, options.quick ? 50 : 1000);
  furnace_section(md, options);
  comparison_section(md, dfg.table, kc.table);
  return md.str();
}

}  // namespace ganzfeld::bench
