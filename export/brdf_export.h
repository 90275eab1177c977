// Writes any model as measured data (models/measured.h): a MERL binary file sampled at the nodes
// of MERL's half/difference grid — a generator for testing readers and pipelines, since no
// measured file can be downloaded here — and ganzfeld's tabulated text format on a regular grid.
#pragma once

#include <string>
#include <vector>

#include "models/measured.h"
#include "models/model.h"

namespace ganzfeld::exporting {

/// The model sampled at every MERL node (kh, kd, kp): f(i, j) divided by each channel's scale
/// (a grey model gives the same f in all three channels), -1 where i or j falls below the
/// horizon (MERL's mark for invalid samples). Returns the file's bytes.
std::vector<char> merl_bytes(const Model& model);
/// merl_bytes written atomically.
void write_merl(const Model& model, const std::string& path);

/// The model on a regular grid: `counts` = {theta_i, theta_r, phi} nodes over [0, 90] x [0, 90]
/// x [0, 180] degrees (each >= 2), as TabulatedBrdf.
TabulatedBrdf tabulate(const Model& model, const std::vector<int>& counts);
/// format_tabulated(tabulate(...)) written atomically.
void write_tabulated(const Model& model, const std::vector<int>& counts, const std::string& path);

}  // namespace ganzfeld::exporting
