// Writes any model as measured data (models/measured.h): a MERL binary file sampled at the nodes
// of MERL's half/difference grid — a generator for testing readers and pipelines, since no
// measured file can be downloaded here — and ganzfeld's tabulated text format on a regular grid.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "models/measured.h"
#include "models/model.h"

namespace ganzfeld::exporting {

/// Multiplicative measurement noise: every written value f becomes max(0, f (1 + sigma z)), z a
/// standard normal draw per node (one draw for all three MERL channels), from a generator seeded
/// with `seed`, so that the same arguments write the same bytes. sigma = 0: the model exactly.
struct Noise {
  double sigma = 0.0;
  std::uint64_t seed = 1;
};
/// Refuses a sigma that is not finite or outside [0, 1] (one-line InputError naming --noise).
void validate_noise(const Noise& noise);

/// The model sampled at every MERL node (kh, kd, kp): f(i, j) divided by each channel's scale
/// (a grey model gives the same f in all three channels), -1 where i or j falls below the
/// horizon (MERL's mark for invalid samples). Returns the file's bytes.
std::vector<char> merl_bytes(const Model& model, const Noise& noise = {});
/// merl_bytes written atomically.
void write_merl(const Model& model, const std::string& path, const Noise& noise = {});

/// The model on a regular grid: `counts` = {theta_i, theta_r, phi} nodes over [0, 90] x [0, 90]
/// x [0, 180] degrees (each >= 2), as TabulatedBrdf.
TabulatedBrdf tabulate(const Model& model, const std::vector<int>& counts, const Noise& noise = {});
/// format_tabulated(tabulate(...)) written atomically.
void write_tabulated(const Model& model, const std::vector<int>& counts, const std::string& path,
                     const Noise& noise = {});

}  // namespace ganzfeld::exporting
