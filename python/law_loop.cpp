// ganzfeld-law-loop: the C++ library's own loop over many directions, without Python, for
// docs/python.md (scripts/bench-python): what a C++ user writes against find_package(ganzfeld):
// each pair normalized as `ganzfeld eval` normalizes --i/--j, then evaluate_law (integrate/laws.h)
// in a oneTBB parallel_for. The Python module's model.g over the same pairs computes the same
// integrals (the same bits), so the ratio of the two times is what the binding costs.
//
//   ganzfeld-law-loop SPEC LAW TOL PAIRS_FILE REPEATS
// PAIRS_FILE: raw little-endian float64, 6 per pair (i x, y, z, j x, y, z). Prints one JSON
// document: {"pairs", "seconds": [each repeat], "median", "evaluations", "value_sum"}.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "integrate/laws.h"
#include "models/spec.h"
#include "util/error.h"
#include "util/timing.h"

namespace {

std::vector<ganzfeld::Vec3> read_pairs(const std::string& path, std::vector<ganzfeld::Vec3>& j) {
  std::ifstream in(path, std::ios::binary);
  std::vector<double> raw;
  for (double x; in.read(reinterpret_cast<char*>(&x), sizeof x);) raw.push_back(x);
  if (raw.empty() || raw.size() % 6 != 0)
    throw ganzfeld::InputError("'" + path + "' holds no whole pairs; expected 6 float64 per pair");
  std::vector<ganzfeld::Vec3> i;
  for (std::size_t k = 0; k < raw.size(); k += 6) {
    const ganzfeld::Vec3 a{raw[k], raw[k + 1], raw[k + 2]}, b{raw[k + 3], raw[k + 4], raw[k + 5]};
    i.push_back(a / glm::length(a));
    j.push_back(b / glm::length(b));
  }
  return i;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::cerr << "usage: ganzfeld-law-loop SPEC LAW TOL PAIRS_FILE REPEATS\n";
    return 2;
  }
  try {
    const ganzfeld::ModelPtr model = ganzfeld::parse_model(argv[1]);
    const ganzfeld::Law law = ganzfeld::parse_law(argv[2]);
    ganzfeld::CubatureOptions options;
    options.abs_tol = std::stod(argv[3]);
    ganzfeld::check_tolerance("TOL", options.abs_tol);
    std::vector<ganzfeld::Vec3> j;
    const std::vector<ganzfeld::Vec3> i = read_pairs(argv[4], j);
    std::vector<ganzfeld::Estimate> out(i.size());
    const std::vector<double> seconds = ganzfeld::util::time_runs(std::stoi(argv[5]), [&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, i.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t m = r.begin(); m != r.end(); ++m)
          out[m] = ganzfeld::evaluate_law(*model, law, i[m], j[m], options);
      });
    });
    long long evaluations = 0;
    double value_sum = 0.0;
    for (const ganzfeld::Estimate& e : out) {
      evaluations += e.evaluations;
      value_sum += e.value;
    }
    std::cout << nlohmann::ordered_json{{"pairs", i.size()},
                                        {"seconds", seconds},
                                        {"median", ganzfeld::util::median(seconds)},
                                        {"evaluations", evaluations},
                                        {"value_sum", value_sum}}
                     .dump()
              << "\n";
    return 0;
  } catch (const ganzfeld::InputError& e) {
    std::cerr << "ganzfeld-law-loop: " << e.what() << "\n";
    return 2;
  }
}
