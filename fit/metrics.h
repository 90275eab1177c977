// The error metrics a fit minimizes and reports, over the samples of fit/samples.h (w_s the
// solid-angle measure of sample s, c_s = cos θ_i of its incident direction, d_s the data's f,
// m_s the model's f):
//
//  ngan  Ngan, Durand & Matusik 2005, "Experimental Analysis of BRDF Models" (EGSR), their fitting
//        error: the cosine-weighted L2 distance E = sqrt(Σ w_s (d_s c_s − m_s c_s)² / Σ w_s) in 1/sr (rms);
//        reported also relative to the data's own norm, E_rel = sqrt(Σ w_s (d_s − m_s)² c_s² /
//        Σ w_s d_s² c_s²), which compares materials of any albedo (0: a perfect fit, 1: as far as
//        a black surface is). Both have the same minimizer; the fit minimizes E_rel².
//  log   Löw, Kronander, Ynnerman & Unger 2012, "BRDF Models for Accurate and Efficient Rendering
//        of Glossy Surfaces" (ACM TOG 31(1)), their fitting error: the compressed, cosine-weighted
//        metric E_log = sqrt(Σ w_s [ln(1 + d_s c_s) − ln(1 + m_s c_s)]² / Σ w_s), used for MERL fits
//        because it weighs the diffuse floor against the specular peak instead of letting the
//        peak's thousands of 1/sr dominate.
#pragma once

#include <string>
#include <vector>

#include "fit/samples.h"

namespace ganzfeld::fit {

enum class Metric { ngan, log };
const char* to_string(Metric metric);
/// Throws InputError naming the text and the metrics allowed.
Metric parse_metric(const std::string& text);

struct MetricValues {
  double ngan_rms = 0.0;       ///< Ngan et al.'s E, 1/sr
  double ngan_relative = 0.0;  ///< E_rel (dimensionless)
  double log_rms = 0.0;        ///< Löw et al.'s E_log (dimensionless)
};

/// The model's f at every sample (in parallel; f_batch per block).
std::vector<double> model_values(const FitData& data, const Model& model);

/// All metrics of model values `m` against the data.
MetricValues measure(const FitData& data, const std::vector<double>& m);
/// The objective a fit minimizes under `metric`: E_rel² or E_log².
double objective(Metric metric, const MetricValues& values);

}  // namespace ganzfeld::fit
