#include "fit/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <utility>

#include "export/brdf_export.h"
#include "fit/parameters.h"
#include "models/registry.h"
#include "models/spec.h"
#include "reports/disk.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::fit {

namespace {

// The data sets. A plastic (a dielectric, F_0 = 0.04, with a sharp Beckmann lobe over a diffuse
// base), a rough metal, a Ward surface and a rough diffuse one.
const char* kPlastic = "cook-torrance:kd=0.3,ks=0.7,m=0.05,eta=1.5,k=0";
const char* kMetal = "ggx:alpha=0.15,f0=0.9";
const char* kWardData = "ward:rho_d=0.3,rho_s=0.15,alpha=0.12";
const char* kRough = "oren-nayar:sigma=0.5,rho=0.8";

/// Recovery: known parameters, none at a bound (a relative error needs a truth away from 0).
const std::vector<std::string> kRecoveryTruths = {
    "ggx:alpha=0.2,f0=0.6",
    "cook-torrance:kd=0.3,ks=0.6,m=0.2,eta=1.5,k=0.5",
    "ward:rho_d=0.4,rho_s=0.2,alpha=0.15",
    "blinn-phong:kd=0.4,ks=0.3,n=50",
    "oren-nayar:sigma=0.4,rho=0.7",
    "lafortune:kd=0.3,Cx=-0.9,Cy=-0.9,Cz=0.8,n=15",
    "hvd-fit:cd=0.4,f0=0.05,f90=0.8,k=0.3,n1=200,r1=0.3,n2=20,r2=0.6",
    "hvd-empirical:cd=0.4,f0=0.1,k=0.2,ns=150,nr=20,rs=0.6,rr=0.5",
    "phong-lewis:kd=0.3,ks=0.5,n=40",
};
const std::vector<std::string> kFitModels = {"ggx",           "lambert + ggx", "cook-torrance", "ward",
                                             "blinn-phong",   "lafortune",     "oren-nayar",    "hvd-fit",
                                             "hvd-empirical", "phong-lewis"};

/// The relative noise of the noisy recovery files, and their seed.
constexpr double kNoise = 0.01;
constexpr std::uint64_t kNoiseSeed = 7;
/// Repeated runs of each noise-free recovery fit, for the median and spread of its time.
constexpr int kTimingRepeats = 3;
/// The targets: relative parameter error and wall time of a recovery, models recovered.
constexpr double kRecoveryTolerance = 1e-3, kRecoverySeconds = 60.0;
constexpr int kRecoveryModels = 6, kCrossModels = 8, kCrossData = 4;
/// Laws of data and fit to this absolute tolerance.
constexpr double kLawTolerance = 1e-5;
/// The disk view's shape (Edwards et al., §5 on Fig. 13): from 45° to 75° the lump's spread on the
/// disk falls by at least this fraction (and by more than from 0° to 45°).
constexpr double kTightening = 0.25;

std::string model_name(const std::string& spec) { return canonical_spec(spec).terms.front().model.name; }

std::string g3(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}
std::string f1(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", x);
  return buf;
}
std::string f3(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", x);
  return buf;
}

/// A directory for the report's MERL files, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "ganzfeld-fit-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary directory for the report");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

struct Setup {
  explicit Setup(const ReportOptions& o) : options(o) {}
  const ReportOptions& options;
  TempDir temp;
  SampleOptions sampling;
  int starts = 4, max_evaluations = FitOptions{}.max_evaluations;
  int files = 0;
  void log(const std::string& line) const {
    if (options.log) options.log(line);
  }
  /// `export-brdf --model spec [--noise …]` into the temporary directory; the path.
  std::string write_data(const std::string& spec, double noise) {
    const std::string path = temp.file("data" + std::to_string(files++) + ".binary");
    exporting::write_merl(*parse_model(spec), path, {noise, kNoiseSeed});
    return path;
  }
  FitOptions fit_options(Metric metric, LocalSearch local = LocalSearch::praxis) const {
    FitOptions o;
    o.metric = metric;
    o.local = local;
    o.starts = starts;
    o.max_evaluations = max_evaluations;
    return o;
  }
};

/// The specs that make the same BRDF as `truth` under a relabeling of its parameters: hvd-fit's two
/// lumps swap with k -> 1 - k (eq. 35), so a fit may land on either labeling.
std::vector<std::string> equivalent_truths(const std::string& truth) {
  std::vector<std::string> out{truth};
  if (model_name(truth) != "hvd-fit") return out;
  ModelSpec swapped = canonical_spec(truth).terms.front().model;
  ParamValues& v = swapped.values;
  v.at("k") = 1.0 - v.at("k");
  std::swap(v.at("n1"), v.at("n2"));
  std::swap(v.at("r1"), v.at("r2"));
  out.push_back(spec_text(swapped));
  return out;
}

RecoveryRow recover(Setup& setup, const std::string& truth, double noise, int repeats, LocalSearch local) {
  RecoveryRow row;
  row.truth = truth;
  row.noise = noise;
  row.local = local;
  const std::string path = setup.write_data(truth, noise);
  const std::string name = model_name(truth);
  for (int r = 0; r < repeats; ++r) {
    const util::Stopwatch watch;
    const double cpu = util::process_cpu_seconds();
    const ModelPtr data = parse_model("merl:file=" + path);
    row.result = fit_model(sample_data(*data, setup.sampling), name, setup.fit_options(Metric::ngan, local));
    row.seconds.push_back(watch.seconds());
    row.cpu_seconds.push_back(util::process_cpu_seconds() - cpu);
  }
  std::filesystem::remove(path);
  // The errors against the nearest equivalent labeling of the truth.
  for (const std::string& equivalent : equivalent_truths(truth)) {
    const std::vector<std::pair<std::string, double>> truth_values = ParameterSpace(name, {}).values_of(equivalent);
    std::vector<ParameterError> errors;
    double worst = 0.0;
    for (const auto& [pname, fitted] : row.result.parameters) {
      const std::string& wanted = pname;  // clang 14 cannot capture a structured binding
      const auto it =
          std::find_if(truth_values.begin(), truth_values.end(), [&](const auto& t) { return t.first == wanted; });
      if (it == truth_values.end()) continue;
      errors.push_back({pname, it->second, fitted, std::abs(fitted - it->second) / std::abs(it->second)});
      worst = std::max(worst, errors.back().relative);
    }
    if (row.errors.empty() || worst < row.max_relative) {
      row.errors = errors;
      row.max_relative = worst;
      row.equivalent = equivalent != truth;
    }
  }
  setup.log("recovery " + truth + (noise > 0 ? " (noise " + g3(noise) + ")" : "") + " [" + to_string(local) +
            "]: max relative error " + g3(row.max_relative) + ", " + f1(util::median(row.seconds)) + " s");
  return row;
}

/// One data set as MERL file, its samples and its laws.
struct DataSet {
  std::string label, spec, path;
  ModelPtr model;
  FitData samples;
  std::vector<LawPoint> laws;
};

DataSet load_data(Setup& setup, const std::string& spec) {
  DataSet d;
  d.spec = spec;
  d.label = model_name(spec);
  d.path = setup.write_data(spec, 0.0);
  d.model = parse_model("merl:file=" + d.path);
  d.samples = sample_data(*d.model, setup.sampling);
  d.laws = data_laws(*d.model, setup.options.quick ? 1e-4 : kLawTolerance);
  return d;
}

FitRow fit_row(const Setup& setup, const DataSet& data, const std::string& model, Metric metric) {
  FitRow row;
  row.data_label = data.label;
  row.data_spec = data.spec;
  row.model = model;
  row.metric = metric;
  row.result = fit_model(data.samples, model, setup.fit_options(metric));
  row.laws = law_difference(data.laws, *parse_model(row.result.spec), setup.options.quick ? 1e-4 : kLawTolerance);
  setup.log("fit " + model + " to " + data.label + " (" + to_string(metric) + "): E_log " +
            g3(row.result.metrics.log_rms) + ", E_rel " + g3(row.result.metrics.ngan_relative) + ", " +
            f1(row.result.seconds) + " s" + (row.result.converged ? "" : ", not converged"));
  return row;
}

std::string today() {
  const std::time_t now = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", std::gmtime(&now));
  return buf;
}

std::string figures_dir(const ReportOptions& options) {
  if (!options.figures.empty()) return options.figures;
  const std::filesystem::path parent = std::filesystem::path(options.markdown).parent_path();
  return (parent / "figures").string();
}

}  // namespace

int Report::targets_met() const {
  return static_cast<int>(std::count_if(targets.begin(), targets.end(), [](const Target& t) { return t.met; }));
}

Report run_report(const ReportOptions& options) {
  const util::Stopwatch watch;
  Report report;
  report.machine = util::machine_description();
  report.date = today();
  Setup setup(options);
  if (options.quick) {  // the smoke test: every part, a few small fits
    setup.sampling.grid = {90, 10, 10};
    setup.starts = 1;
    setup.max_evaluations = 300;
  }

  // 1. Recovery, noise-free (timed, repeated) and noisy.
  const std::vector<std::string> truths =
      options.quick ? std::vector<std::string>{"ward:rho_d=0.4,rho_s=0.2,alpha=0.15",
                                               "hvd-fit:cd=0.4,f0=0.05,f90=0.8,k=0.3,n1=200,r1=0.3,n2=20,r2=0.6"}
                    : kRecoveryTruths;
  for (const std::string& truth : truths)
    report.recovery.push_back(recover(setup, truth, 0.0, options.quick ? 1 : kTimingRepeats, LocalSearch::praxis));
  for (const std::string& truth : truths)
    report.recovery.push_back(recover(setup, truth, kNoise, 1, LocalSearch::praxis));
  if (!options.quick)
    for (const char* truth : {"cook-torrance:kd=0.3,ks=0.6,m=0.2,eta=1.5,k=0.5",
                              "hvd-fit:cd=0.4,f0=0.05,f90=0.8,k=0.3,n1=200,r1=0.3,n2=20,r2=0.6"})
      for (LocalSearch local : {LocalSearch::praxis, LocalSearch::bobyqa})
        report.local_searches.push_back(recover(setup, truth, 0.0, 1, local));

  // 2 and 3. The data sets, each written once.
  const std::vector<std::string> data_specs = options.quick
                                                  ? std::vector<std::string>{kPlastic, kWardData}
                                                  : std::vector<std::string>{kPlastic, kMetal, kWardData, kRough};
  std::vector<DataSet> data;
  for (const std::string& spec : data_specs) data.push_back(load_data(setup, spec));
  const std::vector<std::string> fit_models = options.quick ? std::vector<std::string>{"ggx", "hvd-fit"} : kFitModels;
  report.fit_models = fit_models;
  for (const DataSet& d : data) report.data_models.push_back(d.spec);

  // 2. Two lumps against ggx and ward, both metrics, on the plastic and the metal.
  const std::vector<std::string> lump_models =
      options.quick ? std::vector<std::string>{"hvd-fit"} : std::vector<std::string>{"hvd-fit", "ggx", "ward"};
  for (const DataSet& d : data) {
    if (d.spec != kPlastic && d.spec != kMetal) continue;
    for (Metric metric : {Metric::log, Metric::ngan})
      for (const std::string& model : lump_models) report.lumps.push_back(fit_row(setup, d, model, metric));
  }

  // 3. Cross-model: each fit model on each other model's data, under the log metric.
  for (const DataSet& d : data)
    for (const std::string& model : fit_models)
      if (model != d.label) report.cross.push_back(fit_row(setup, d, model, Metric::log));

  // 4. The disk view of the plastic and its two-lump fit under the log metric.
  const auto plastic_fit = std::find_if(report.lumps.begin(), report.lumps.end(), [](const FitRow& r) {
    return r.data_spec == kPlastic && r.model == "hvd-fit" && r.metric == Metric::log;
  });
  const DataSet& plastic = data.front();
  report.disk_data = plastic.spec;
  report.disk_fit = plastic_fit->result.spec;
  const std::string dir = figures_dir(options);
  std::filesystem::create_directories(dir);
  report.disk_figure = (std::filesystem::path(dir) / "fit-disk-plastic.png").string();
  write_disk_figure(*plastic.model, parse_model(report.disk_fit).get(), DiskOptions{}, report.disk_figure);
  report.disk_command = "ganzfeld export-brdf --model " + plastic.spec +
                        " -o plastic.binary && ganzfeld figure --disk " +
                        "--model merl:file=plastic.binary --compare '" + report.disk_fit + "' -o " + report.disk_figure;
  const ModelPtr disk_fit = parse_model(report.disk_fit);
  for (double t : DiskOptions{}.theta_o_deg)
    report.disk.push_back({t, disk_spread(*plastic.model, t), disk_spread(*disk_fit, t)});

  // The targets.
  {
    int recovered = 0;
    double worst = 0.0, slowest = 0.0;
    for (const RecoveryRow& r : report.recovery) {
      if (r.noise > 0.0) continue;
      const double seconds = util::median(r.seconds);
      if (r.max_relative <= kRecoveryTolerance && seconds <= kRecoverySeconds) ++recovered;
      worst = std::max(worst, r.max_relative);
      slowest = std::max(slowest, seconds);
    }
    report.targets.push_back(
        {"Synthetic recovery: parameters of >= 6 models recovered to <= 1e-3 relative from noise-free "
         "data made by export-brdf, in <= 60 s each on 2 cores",
         std::to_string(recovered) + " models recovered to <= 1e-3 in <= 60 s (worst error " + g3(worst) +
             ", slowest median " + f1(slowest) + " s wall)",
         recovered >= kRecoveryModels});
  }
  {
    bool all = !report.lumps.empty();
    for (const char* d : {kPlastic, kMetal})
      for (const char* m : {"hvd-fit", "ggx", "ward"})
        all = all && std::any_of(report.lumps.begin(), report.lumps.end(),
                                 [&](const FitRow& r) { return r.data_spec == d && r.model == m; });
    report.targets.push_back(
        {"hvd-fit with two lumps fitted to cook-torrance- and ggx-made data: metric values published "
         "beside ggx's and ward's own fits to the same data",
         std::to_string(report.lumps.size()) + " fits published (part 2)", all});
  }
  report.targets.push_back(
      {"Cross-model table: each of >= 8 models fitted to the data of each of >= 4 others, with the "
       "metrics and the differences of g, h, a",
       std::to_string(fit_models.size()) + " models x " + std::to_string(data.size()) + " data sets, " +
           std::to_string(report.cross.size()) + " fits",
       static_cast<int>(fit_models.size()) >= kCrossModels && static_cast<int>(data.size()) >= kCrossData});
  {
    // Flat, then tightening: the spread falls less from 0° to 45° than from 45° to 75°, and by at
    // least kTightening from 45° to 75°.
    auto spread_at = [&](double t, bool fit) {
      const auto it =
          std::find_if(report.disk.begin(), report.disk.end(), [&](const DiskRow& r) { return r.theta_o_deg == t; });
      return fit ? it->fit_spread : it->data_spread;
    };
    auto drops = [&](bool fit) {
      return std::make_pair(1.0 - spread_at(45.0, fit) / spread_at(0.0, fit),
                            1.0 - spread_at(75.0, fit) / spread_at(45.0, fit));
    };
    auto shape = [&](bool fit) {
      const auto [early, late] = drops(fit);
      return early < late && late >= kTightening;
    };
    auto numbers = [&](bool fit) {
      const auto [early, late] = drops(fit);
      return f3(spread_at(0.0, fit)) + "/" + f3(spread_at(45.0, fit)) + "/" + f3(spread_at(75.0, fit)) + " (" +
             f1(100 * early) + "% narrower from 0 to 45 deg, " + f1(100 * late) + "% from 45 to 75 deg)";
    };
    report.targets.push_back(
        {"The disk view reproduces the shape of Edwards et al.'s Fig. 13 for a plastic-like dataset "
         "(two lumps): the data's halfway vectors about constant to 45 deg, then tightening",
         "lump spread on the orthogonal disk at 0/45/75 deg: " + numbers(false), shape(false)});
    report.targets.push_back({"... and the two-lump fit (constant parameters, as fitted here) follows that shape",
                              "fit's spread at 0/45/75 deg: " + numbers(true), shape(true)});
  }
  report.seconds = watch.seconds();
  return report;
}

std::string report_markdown(const Report& report, const ReportOptions& options) {
  std::ostringstream md;
  md << "# Fitting BRDFs to data: `ganzfeld fit`\n\n";
  md << "<!-- Generated by `" << options.command << "`; do not edit by hand. -->\n\n";
  md << "Generated by `" << options.command << "` (scripts/gen-fitting-docs, which stamps the commit) on "
     << report.date << ", commit " << options.commit << ", on " << report.machine << " (read from the machine), in "
     << f1(report.seconds / 60.0)
     << " min. **The machine is shared with other agents' builds and tests**: wall times include waiting for a core; "
        "the CPU time beside them is what the fits themselves used (both cores together).";
  if (options.quick)
    md << " **Quick mode**: a few small fits, as the test suite runs it; the targets need the full run.";
  md << "\n\n";

  md << R"(`ganzfeld fit` fits the free parameters of any registered model — or a mixture such as
`lambert + ggx` — to measured data (`merl:file=…`, `tabulated:file=…`) or to any model spec
(synthetic data), and prints the fitted spec, the metrics, the fit's convergence and the laws
g, h, a of data and fit:

```sh
ganzfeld export-brdf --model cook-torrance:kd=0.3,ks=0.7,m=0.05,eta=1.5,k=0 -o plastic.binary
ganzfeld fit --data merl:file=plastic.binary --model hvd-fit --metric log
ganzfeld fit --data merl:file=plastic.binary --model "lambert + ggx" --fixed ggx.f0=0.04 --json
ganzfeld figure --disk --model merl:file=plastic.binary --compare 'hvd-fit:…' -o disk.png
```

Flags: `--start SPEC` (the first start's values), `--fixed KEY=V,…` (held; a mixture's keys are
`LABEL.KEY` and `LABEL.weight`), `--metric ngan|log`, `--grid` (sample nodes), `--max-theta`
(default 80°), `--starts` (default 4), `--max-evals` per start, `--max-seconds`, `--local
praxis|bobyqa`, `--tol` (laws), `--json`. Ctrl-C stops the search and prints the best fit so far
with `converged: false`. Code: `fit/` (samples, metrics, parameters, the optimizer, the laws of
data and fit, this report), `reports/disk.cpp` (the disk view); tests: `tests/fit_test.cpp`,
`tests/fit_cli_test.sh`.

## The optimizer: NLopt, not Ceres

Both are Debian packages (`libnlopt-cxx-dev`, `libceres-dev`). The problem is a nonlinear least
squares problem — a residual per sample — which is what Ceres is built for, but three things
decide for NLopt:

- **Derivatives.** ganzfeld's models return f only (no templated jets, and measured data have no
  derivative at all), so Ceres would differentiate numerically: n + 1 or 2n passes over the
  samples per Jacobian, with steps that know nothing of the registry's bounds (a step past
  `kd + ks ≤ 1` or a range end makes no model). NLopt's derivative-free methods build their
  models from the objective's own values and keep every point inside the bounds.
- **Bounds and infeasible points.** Every parameter has a registry range, and NLopt takes them as
  bounds directly; points a model's factory refuses get a finite penalty the search walks away from.
- **Weight.** `libnlopt-cxx-dev` is four small packages; `libceres-dev` pulls 27 (SuiteSparse,
  ATLAS, glog, gflags, Eigen). Fitting is optional (`fit/` is built only where NLopt is found, as
  the benchmark only where libcubature is), and a light dependency keeps it so.

The local search is **PRAXIS** (Brent 1973, the principal-axis method), not BOBYQA: hvd-fit's
lump radius R and exponent n trade off along a narrow curved valley (a sharp lump's width is set
by n/R² alone), and conjugate directions follow it where BOBYQA's trust regions crawl — measured
below ("PRAXIS and BOBYQA"). Several starts: the start spec's values, then Halton points in the
unit box; a start that reproduces the data to eight digits (objective < 1e-16) ends the search.
Converged means that the local search which found the best point stopped on its step or
objective tolerance, not on its evaluation budget, a time limit or an interruption; a fit that
does not converge still prints its best point and says so (`converged: false`).

Parameters: the real-valued items of the model's canonical spec (`ggx`: alpha and f0, not the
choice g2; integers are never varied), in the registry's ranges, each mapped to [0, 1] linearly,
logarithmically (ranges of 20:1 and more, e.g. radii) or as log(1 + x) (exponents from 0 to 10⁶),
so that a step means the same relative change across decades.

## The metrics

Over the samples s (w_s the solid-angle measure dω_i dω_o of the sample's cell, c_s = cos θ_i,
d_s the data's f, m_s the model's f):

- **ngan** — Ngan, Durand & Matusik 2005, "Experimental Analysis of BRDF Models" (EGSR): the
  cosine-weighted L2 distance E = sqrt(Σ w_s (d_s c_s − m_s c_s)² / Σ w_s), in 1/sr, and, to
  compare materials of any albedo, its **relative** form E_rel = sqrt(Σ w_s (d_s − m_s)² c_s² /
  Σ w_s d_s² c_s²) (0: a perfect fit; 1: as far off as a black surface). Same minimizer; the fit
  minimizes E_rel².
- **log** — Löw, Kronander, Ynnerman & Unger 2012, "BRDF Models for Accurate and Efficient
  Rendering of Glossy Surfaces" (ACM TOG 31(1)): E_log = sqrt(Σ w_s [ln(1 + d_s c_s) −
  ln(1 + m_s c_s)]² / Σ w_s), the metric commonly used for MERL fits: the logarithm weighs the
  diffuse floor against the specular peak, which under E lets its hundreds of 1/sr dominate.

Samples: a MERL file's own nodes (every node of the 90 × 90 × 180 (θ_h, θ_d, φ_d) grid or every
s-th along each axis; default 90 × 30 × 30), a tabulated file's own nodes, or, for a model spec,
the same MERL-like grid evaluated; pairs with θ_i or θ_o beyond 80° are left out, as Ngan et al.
leave out grazing measurements. The measure of a node is that of its cell, dω_i dω_o = 4 cos θ_d
dω_h dω_d (Rusinkiewicz's change of variables), integrated exactly over the cell; over all valid
pairs the measures sum to (2π)² (tested). Each pair is rotated about n by a golden-ratio azimuth
(the data are isotropic), so an anisotropic fit model sees every azimuth.

)";

  md << "## Targets\n\n| target | verdict | measured |\n|---|---|---|\n";
  for (const Target& t : report.targets)
    md << "| " << t.what << " | **" << (t.met ? "met" : "missed") << "** | " << t.number << " |\n";

  md << "\n## 1. Synthetic recovery\n\nEach model's known parameters written as a MERL file by "
        "`export-brdf` (noise-free, then with multiplicative noise σ = "
     << g3(kNoise) << ", seed " << kNoiseSeed
     << "), read back as `merl:file=…`, fitted from the registry's default start under the ngan metric. "
        "Error: the largest |fitted − true| / |true| over the free parameters (which one in brackets); for "
        "hvd-fit against the nearer of the two labelings of its lumps (eq. 35 is unchanged by swapping them with "
        "k -> 1 - k). "
        "Time: reading and sampling the file plus the fit, "
     << (options.quick ? 1 : kTimingRepeats)
     << " runs for the noise-free files (median, min–max), wall and CPU.\n\n"
        "| data (export-brdf --model) | noise | free | max relative error | E_rel | converged | evaluations | wall s | "
        "CPU s |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  for (const RecoveryRow& r : report.recovery) {
    const auto worst =
        std::max_element(r.errors.begin(), r.errors.end(),
                         [](const ParameterError& a, const ParameterError& b) { return a.relative < b.relative; });
    const auto [mn, mx] = std::minmax_element(r.seconds.begin(), r.seconds.end());
    md << "| `" << r.truth << "` | " << (r.noise > 0 ? g3(r.noise) : "0") << " | " << r.errors.size() << " | "
       << g3(r.max_relative) << (worst != r.errors.end() ? " (" + worst->name + ")" : "")
       << (r.equivalent ? ", lumps swapped" : "") << " | " << g3(r.result.metrics.ngan_relative) << " | "
       << (r.result.converged ? "yes" : "**no**: " + r.result.stop_reason) << " | " << r.result.evaluations << " | "
       << f1(util::median(r.seconds)) << (r.seconds.size() > 1 ? " (" + f1(*mn) + "–" + f1(*mx) + ")" : "") << " | "
       << f1(util::median(r.cpu_seconds)) << " |\n";
  }
  md << "\nWith noise the fit's E_rel is the noise level itself (the data's own scatter), and the parameters move "
        "by what that scatter allows.\n";

  if (!report.local_searches.empty()) {
    md << "\n### PRAXIS and BOBYQA\n\nThe same noise-free recoveries with either local search (one run each, "
          "4 starts, "
       << FitOptions{}.max_evaluations
       << " evaluations per start at most):\n\n"
          "| data | local search | max relative error | converged | evaluations | wall s | CPU s "
          "|\n|---|---|---|---|---|---|---|\n";
    for (const RecoveryRow& r : report.local_searches)
      md << "| `" << r.truth << "` | " << to_string(r.local) << " | " << g3(r.max_relative) << " | "
         << (r.result.converged ? "yes" : "**no**: " + r.result.stop_reason) << " | " << r.result.evaluations << " | "
         << f1(r.seconds.front()) << " | " << f1(r.cpu_seconds.front()) << " |\n";
  }

  auto fit_table = [&](const std::vector<FitRow>& rows, bool with_metric) {
    md << "| data | model | " << (with_metric ? "minimized | " : "")
       << "E_log | E_rel | E (1/sr) | max \\|Δg\\| | max \\|Δh\\| | max \\|Δa\\| | converged | wall s | fitted spec "
          "|\n|---|---|"
       << (with_metric ? "---|" : "") << "---|---|---|---|---|---|---|---|---|\n";
    for (const FitRow& r : rows) {
      const MetricValues& m = r.result.metrics;
      md << "| " << r.data_label << " | " << r.model << " | "
         << (with_metric ? std::string(to_string(r.metric)) + " | " : "") << g3(m.log_rms) << " | "
         << g3(m.ngan_relative) << " | " << g3(m.ngan_rms) << " | " << g3(r.laws.max_g) << " | " << g3(r.laws.max_h)
         << " | " << g3(r.laws.max_a) << (r.laws.converged ? "" : " (not converged)") << " | "
         << (r.result.converged ? "yes" : "**no**: " + r.result.stop_reason) << " | " << f1(r.result.seconds) << " | `"
         << r.result.spec << "` |\n";
    }
  };
  const std::string law_points =
      "The laws are compared at h(θ_j) and a(θ_i) for θ ∈ {0, 30, 60, 80}° and g at (θ_i, θ_j, φ) ∈ {(30, 0, 0), "
      "(60, 45, 0), (60, 45, 180), (120, 30, 0)}°, each by the cubature to " +
      g3(options.quick ? 1e-4 : kLawTolerance) +
      " absolute; the data's laws are those of the MERL file (its multilinear interpolant), which for a "
      "non-reciprocal model (the hvd ones) keeps f(i, j) on one half of φ_d and mirrors it onto the other.";

  md << "\n## 2. Two lumps: hvd-fit beside ggx and ward\n\nEdwards et al. (§5) fit their data-fitting BRDF, two lumps "
        "on the halfway-vector disk (eq. 34–36), to MERL materials \"extremely well using only a small set of "
        "parameters\" — by hand, with per-ω_o parameters. Here the same model, with constant parameters, fitted by "
        "the optimizer to the plastic (`"
     << kPlastic << "`) and the metal (`" << kMetal
     << "`), beside ggx's and ward's own fits to the same files, each under both metrics.\n\n";
  fit_table(report.lumps, true);
  md << "\n" << law_points << "\n";

  md << "\n## 3. Cross-model table\n\nEach model fitted (log metric, from its registry defaults, "
     << (options.quick ? 1 : 4) << " starts) to the MERL file of each other model's data:\n\n";
  for (const std::string& d : report.data_models) md << "- `" << d << "`\n";
  md << "\nE_log at a glance (rows: the fit model; columns: the data):\n\n| model |";
  for (const std::string& d : report.data_models) md << " " << model_name(d) << " |";
  md << "\n|---|";
  for (std::size_t k = 0; k < report.data_models.size(); ++k) md << "---|";
  md << "\n";
  for (const std::string& m : report.fit_models) {
    md << "| " << m << " |";
    for (const std::string& d : report.data_models) {
      const auto it = std::find_if(report.cross.begin(), report.cross.end(),
                                   [&](const FitRow& r) { return r.data_spec == d && r.model == m; });
      md << " "
         << (it == report.cross.end()
                 ? "(own data)"
                 : g3(it->result.metrics.log_rms) + (it->result.converged ? "" : " (not converged)"))
         << " |";
    }
    md << "\n";
  }
  md << "\nOn the rough diffuse data most models end at the same E_log: the best Lambertian surface they can "
        "become. E_rel in the hundreds or thousands with a small E_log marks a lump shrunk to a spike on a few "
        "samples, which the logarithm barely charges. Every fit, with the extended-source view of its error — how "
        "far the laws of the fit are from the data's (a model fitted to its own data shows the file's interpolation "
        "error there, e.g. ggx on the ggx file, part 2):\n\n";
  fit_table(report.cross, false);
  md << "\n" << law_points << "\n";

  md << "\n## 4. The halfway-vector disk view\n\n"
     << "![disk view](" << std::filesystem::path(report.disk_figure).parent_path().filename().string() << "/"
     << std::filesystem::path(report.disk_figure).filename().string() << ")\n\n"
     << "Edwards et al.'s Fig. 13 regenerated for the plastic (`" << report.disk_data
     << "`, red) and its two-lump hvd-fit under the log metric (blue): for each outgoing angle θ_o, halfway vectors "
        "drawn "
        "from each BRDF's density on the disk, in the orthogonal projection (p = ρ) and the scaling projection "
        "(reports/disk.h). The command (the data file first):\n\n```sh\n"
     << report.disk_command
     << "\n```\n\nThe paper (§5): the distribution \"is approximately constant as ω_o goes from normal incidence to "
        "the point where θ_o is approximately π/4. From that point until ω_o approaches grazing angles, the "
        "distribution tightens around the normal direction.\" The lump's spread on the orthogonal disk, sqrt(∫ q |h|² "
        "dA / ∫ q dA) with q the density above its median (the diffuse floor):\n\n| θ_o | data | fit "
        "|\n|---|---|---|\n";
  for (const DiskRow& r : report.disk)
    md << "| " << format_number(r.theta_o_deg) << "° | " << f3(r.data_spread) << " | " << f3(r.fit_spread) << " |\n";
  md << "\nThe shape counts as reproduced when the spread falls less from 0° to 45° than from 45° to 75°, and by at "
        "least "
     << g3(100 * kTightening)
     << "% from 45° to 75°. hvd-fit's lumps sit at the origin of the orthogonal disk with radii that do not depend on "
        "ω_o, so with constant parameters its spread cannot follow; Edwards et al. vary n toward grazing for this "
        "(per-ω_o parameters, not fitted here).\n";

  md << R"(
## Not done

- Per-ω_o parameters (Edwards et al.: "we achieved the best results by increasing the larger of
  n_1 and n_2 as ω_o approaches grazing, and by changing k"): the fits here are constant in ω_o.
- Real measurements: no MERL file can be downloaded here; every data set is made by `export-brdf`,
  and the plastic is a Cook–Torrance stand-in for MERL's plastics.
- The web viewer does not show measured data or fits (serve/ refuses `file=` specs).
)";
  return md.str();
}

}  // namespace ganzfeld::fit
