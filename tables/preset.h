// The tables real-time engines read, over a GGX roughness axis (format version 3,
// tables/param_table.h), every texel an integral of the albedo law a computed by the cubature
// with its error bound:
//
//   dfg (Filament's order, layout "filament"):
//     dfg_fc  = ∫ f₁ (1 − v·h)⁵ cos θ dω   (f₁: GGX with F = 1; = a of ggx:f0=0, Schlick F = (1 − v·h)⁵)
//     dfg_e   = ∫ f₁ cos θ dω              (= a of ggx:f0=1)
//     charlie = ∫ f_charlie cos θ dω       (a of charlie:alpha=α, the sheen channel)
//   dfg, layout "ue4" (Unreal's (scale, bias), Karis 2013): scale = dfg_e − dfg_fc, bias = dfg_fc
//   kulla-conty (Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks"):
//     e     = E(μ, α) = ∫ f₁ cos θ dω
//     e_avg = E_avg(α) = 2 ∫₀¹ E(μ) μ dμ (the law r of ggx:f0=1, its own cubature and error),
//             stored in every texel of its row so that one texture serves both lookups.
//
// α → 0 (a roughness or alpha sample at 0, node grid only): the exact mirror limits, error 0:
// dfg_fc = (1 − μ)⁵, dfg_e = e = e_avg = 1 (F = 1 reflects everything; v·h = μ), charlie = 0
// (the sheen's normals crowd into the surface plane, whose mirror directions lie below it).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "integrate/cubature.h"
#include "models/model.h"
#include "tables/param_table.h"

namespace ganzfeld::tables {

enum class Preset { dfg, kulla_conty };
const char* to_string(Preset preset);  ///< "dfg" or "kulla-conty"
Preset parse_preset(const std::string& text);
enum class DfgLayout { filament, ue4 };
const char* to_string(DfgLayout layout);  ///< "filament" or "ue4"
DfgLayout parse_dfg_layout(const std::string& text);

/// The cubature's tolerance per integral: with float rounding (≤ 6e-8 for values ≤ 1) and a
/// difference of two integrals (ue4's scale) every texel's bound stays below 1e-6. Each texel's
/// bound is the cubature's own error estimate plus that rounding, checked against the
/// independent rule of models/ggx_energy.h in docs/realtime.md.
inline constexpr double kPresetTolerance = 1e-8;
/// The lookup's validation (ParamTable::lookup_error) runs the cubature at this multiple of the
/// bake's tolerance: it measures interpolation between samples, orders of magnitude above it.
inline constexpr double kValidationToleranceRatio = 100.0;

struct PresetOptions {
  Preset preset = Preset::dfg;
  DfgLayout layout = DfgLayout::filament;
  std::string axis = kAxisRoughness;  ///< the parameter axis: roughness (R, α = R²) or alpha
  Grid grid = Grid::texel;
  std::vector<int> resolution{64, 64};  ///< samples on (parameter, cos_theta_i)
  double tolerance = kPresetTolerance;
  long long max_evaluations = CubatureOptions{}.max_evaluations;  ///< per integral
  Encoding encoding = Encoding::single;
  std::function<void(std::uint64_t done, std::uint64_t total)> progress;  ///< as BakeCommon::progress
};

/// The g2 form of an isotropic ggx model, as the family spec "ggx:g2=..."; throws InputError
/// for any other model ("--preset dfg needs a ggx model: 'lambert' has no roughness").
std::string preset_family(const Model& model, const PresetOptions& options);

/// Parses "N" or "NPxNMU" (parameter x cos_theta_i samples, each >= 2).
std::vector<int> parse_preset_resolution(const std::string& text);

/// Bakes the preset for the ggx model's g2 form (its alpha and f0 are replaced by the axis and
/// the channels' definitions). Refuses other models, a bad axis name, resolution or tolerance.
/// Table::command is left for the caller.
ParamTable bake_preset(const Model& model, const PresetOptions& options);

}  // namespace ganzfeld::tables
