// Shared command-line plumbing: direction flags and tolerances.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "integrate/laws.h"

namespace ganzfeld::cli {

/// The direction flags of cli-contract.md: --i/--j X,Y,Z or --theta-i/--theta-j/--phi in degrees.
struct DirectionArgs {
  std::string i_text, j_text;
  std::optional<double> theta_i, theta_j;
  double phi_deg = 0.0;
  void add_to(CLI::App& app);
  /// The incident direction / sky pole; `allow_below` for the law of vignetting (i·n < 0).
  Vec3 incident(Law law) const;
  Vec3 outgoing(Law law) const;
};

/// Parses "X,Y,Z" into a normalized vector; throws InputError naming the flag and the value.
Vec3 parse_vector(const std::string& flag, const std::string& text);

/// Refuses non-finite, non-positive or absurd tolerances with a one-line message.
void validate_tolerance(double tol);


}  // namespace ganzfeld::cli
