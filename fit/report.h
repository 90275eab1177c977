// The fitting report (docs/fitting.md, `ganzfeld fit --report`): every target of the fitting work
// met or missed with its number, measured from files `export-brdf` writes (exporting::write_merl)
// into a temporary directory and removes again (34 MB each):
//  1. synthetic recovery: known models written as MERL files, without and with multiplicative
//     noise, fitted from the registry's default start; the largest relative error of the free
//     parameters, and the fit's wall time (median and spread of repeated runs);
//  2. hvd-fit with two lumps fitted to cook-torrance- and ggx-made data, beside ggx's and ward's
//     own fits to the same data;
//  3. a cross-model table: each fit model fitted to the data of each data model, both metrics and
//     how the laws g, h, a of the fit differ from the data's (fit/law_difference.h);
//  4. the halfway-vector disk view of a plastic-like data set and its two-lump fit
//     (reports/disk.h), and the spread of the lump on the disk per outgoing angle.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fit/fit.h"
#include "fit/law_difference.h"

namespace ganzfeld::fit {

struct ReportOptions {
  bool quick = false;   ///< a small slice (the ctest smoke test)
  std::string command;  ///< the stamp: the command line that generates the report
  std::string commit = "unknown";
  std::string markdown;                         ///< where the report goes (figures beside it unless `figures`)
  std::string figures;                          ///< the directory of the disk figure
  std::function<void(const std::string&)> log;  ///< one line per finished fit
};

struct ParameterError {
  std::string name;
  double truth = 0.0, fitted = 0.0, relative = 0.0;
};

struct RecoveryRow {
  std::string truth;   ///< the spec the data were made from
  double noise = 0.0;  ///< export-brdf --noise
  std::vector<ParameterError> errors;
  double max_relative = 0.0;
  bool equivalent = false;          ///< the errors are against the truth with its lumps swapped (hvd-fit)
  std::vector<double> seconds;      ///< wall time of each repeated fit (data read and sampled included)
  std::vector<double> cpu_seconds;  ///< the process's CPU time of each, both cores together
  LocalSearch local = LocalSearch::praxis;
  FitResult result;  ///< the last run
};

struct FitRow {
  std::string data_label, data_spec;  ///< the data model and the spec it was made from
  std::string model;                  ///< the fit model (its default start)
  Metric metric = Metric::log;        ///< the metric minimized
  FitResult result;
  LawDifference laws;
};

struct DiskRow {
  double theta_o_deg = 0.0, data_spread = 0.0, fit_spread = 0.0;
};

struct Target {
  std::string what, number;
  bool met = false;
};

struct Report {
  std::vector<RecoveryRow> recovery;
  std::vector<RecoveryRow> local_searches;  ///< PRAXIS against BOBYQA on the same recoveries
  std::vector<FitRow> lumps;                ///< part 2
  std::vector<FitRow> cross;                ///< part 3
  std::vector<std::string> data_models, fit_models;
  std::string disk_data, disk_fit, disk_figure, disk_command;
  std::vector<DiskRow> disk;
  std::vector<Target> targets;
  std::string machine, date;
  double seconds = 0.0;
  int targets_met() const;
  int targets_total() const { return static_cast<int>(targets.size()); }
};

Report run_report(const ReportOptions& options);
std::string report_markdown(const Report& report, const ReportOptions& options);

}  // namespace ganzfeld::fit
