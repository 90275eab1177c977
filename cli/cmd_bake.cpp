// ganzfeld bake: one law of one model into an OpenEXR table (lut/, docs/lut-format.md).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "laws/error.h"
#include "laws/registry.h"
#include "laws/spec.h"
#include "lut/bake.h"
#include "lut/exr_io.h"

namespace ganzfeld::cli {

namespace {

struct BakeArgs {
  std::string model, law, res, output, encoding = "float";
  double tol = 1e-9;
  long long max_evaluations = CubatureOptions{}.max_evaluations;
  bool quiet = false, json = false;
  std::string command;  ///< the command line, stamped into the table
};

/// argv joined into a line a POSIX shell reproduces: words with anything but [A-Za-z0-9_./:=,+-]
/// are single-quoted. argv[0] is written as `ganzfeld`.
std::string shell_line(int argc, const char* const* argv) {
  std::string line = "ganzfeld";
  for (int k = 1; k < argc; ++k) {
    const std::string word = argv[k];
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

void add_bake_command(CLI::App& app, Action& action, int argc, const char* const* argv) {
  auto* cmd = app.add_subcommand("bake", "tabulate a law (g, h, a) of a model into an OpenEXR table with per-entry error");
  auto args = std::make_shared<BakeArgs>();
  args->command = shell_line(argc, argv);
  cmd->add_option("--model", args->model, "model spec, e.g. specular:alpha=8 (see `ganzfeld models`)")->required();
  cmd->add_option("--law", args->law, "g (vignetting, 3-D), h (darkening, 1-D) or a (albedo, 1-D)")->required();
  cmd->add_option("--res", args->res,
                  "nodes per axis: N, or NIxNJxNPHI for g (axes cos_theta_i, cos_theta_j, phi); each >= 2")
      ->required();
  cmd->add_option("--tol", args->tol, "absolute tolerance of every entry's cubature (default 1e-9)");
  cmd->add_option("--max-evals", args->max_evaluations,
                  "evaluation budget per entry; beyond it the entry is kept and counted as unconverged");
  cmd->add_option("--encoding", args->encoding, "stored precision: float (default) or half");
  cmd->add_option("-o,--output", args->output, "the table to write, FILE.exr (written atomically)")->required();
  cmd->add_flag("--quiet", args->quiet, "no progress bar (it is shown only when stderr is a terminal)");
  cmd->add_flag("--json", args->json, "print one JSON document");
  cmd->callback([&action, args] {
    action = [args] {
      // Everything is checked before the (possibly long) bake.
      const Law law = parse_law(args->law);
      if (law != Law::g && law != Law::h && law != Law::a)
        throw InputError("--law " + args->law + " cannot be tabulated; allowed: g, h, a");
      const ModelPtr model = parse_model(args->model);
      validate_tolerance(args->tol);
      if (args->max_evaluations < 1000)
        throw InputError("--max-evals=" + std::to_string(args->max_evaluations) + " is too small; allowed: >= 1000");
      lut::BakeOptions options;
      options.resolution = lut::parse_resolution(args->res, law);
      options.tolerance = args->tol;
      options.max_evaluations = args->max_evaluations;
      options.encoding = lut::parse_encoding(args->encoding);
      lut::check_writable(args->output);

      std::shared_ptr<ProgressBar> bar;
      if (!args->quiet && ::isatty(STDERR_FILENO)) {
        bar = std::make_shared<ProgressBar>(std::string("baking ") + to_string(law) + " of " + model->spec());
        options.progress = [bar](std::uint64_t done, std::uint64_t total) { bar->update(done, total); };
      }
      const auto start = std::chrono::steady_clock::now();
      lut::Table table = lut::bake(*model, law, options);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      table.command = args->command;
      lut::write_table(table, args->output);

      std::string nodes;
      for (const lut::Axis& a : table.axes) nodes += (nodes.empty() ? "" : "x") + std::to_string(a.count);
      if (args->json) {
        nlohmann::ordered_json doc{
            {"tables",
             {{{"path", args->output},
               {"model", table.model},
               {"law", to_string(law)},
               {"status", "baked"},
               {"entries", table.entries()},
               {"max_error", table.max_error},
               {"unconverged", table.unconverged},
               {"seconds", seconds}}}}};
        std::cout << doc.dump(2) << "\n";
      } else {
        std::printf("baked %s of %s, %s nodes (%zu entries, %s) in %.2f s: max error %.3g, %lld unconverged -> %s\n",
                    to_string(law), table.model.c_str(), nodes.c_str(), table.entries(),
                    lut::to_string(table.encoding), seconds, table.max_error, table.unconverged,
                    args->output.c_str());
      }
      if (table.unconverged > 0)
        std::cerr << "ganzfeld: warning: " << table.unconverged << " of " << table.entries()
                  << " entries did not reach --tol " << format_number(args->tol) << " within " << args->max_evaluations
                  << " evaluations; their achieved error is stored (max error " << format_number(table.max_error)
                  << ")\n";
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
