// Baking to a requested lookup error (`bake --max-error E [--max-bytes B]`): the baker
// chooses the node counts per axis, the frame and the interpolation so that the validated lookup
// error (Table::lookup_error) is <= E with as few value bytes as it can find, sets the cubature
// tolerance itself (E/kNodeToleranceRatio), and refuses when E cannot be met within B.
//
// The search, in three steps:
//  1. Frame: g of a model whose mass hints show a lobe at the mirror direction or at j gets the
//     lobe frame (tables/frame.h), else the cosines frame; h and a the cosines frame.
//  2. Bake at a coarse resolution, validate (cell centres + kSearchChecks seeded random points
//     against direct cubature at E/kCheckToleranceRatio).
//  3. Per axis, estimate how much error that axis contributes from the table itself: at every
//     odd node, the difference between its value and the interpolation from the even nodes (a
//     grid twice as coarse along that axis), scaled by 2^-p (p = 4 b-spline, 3 Catmull–Rom, 2 linear). The
//     validated error calibrates these estimates; each axis then gets the count that brings its
//     share to E/(margin x axes) (the product of the counts is smallest when the shares are
//     equal), and the interpolation (linear or Catmull–Rom) whose predicted bytes are fewer.
//     Counts whose table would exceed B shrink by one common factor to the largest table of
//     that shape within B (a search that gave up there refused with its coarse first bake).
//     Bake again; stop when lookup_error <= E, when the capped counts repeat a bake, when a larger
//     table did not cut the error as a linear-only search's growth promised, or did not lower it
//     at all in a b-spline search (a feature no node count resolves), or after kMaxSearchBakes bakes.
//
// With a fetch budget N (`--fetches N`), the schemes a shader can read within N texture fetches
// per lookup are searched in the order of their fetches, and the first that meets E is kept:
// one hardware-filtered linear fetch (the warped frame for g of a model with a lobe frame, else
// the cosines frame; the bound covers 8-bit filter weights, tables::Filter), then the same frame
// read with texelFetch and blended in full precision (2^D fetches), then the cubic b-spline of the
// same frame in 2 hardware-filtered fetches per axis (2^D; its bound covers the 8-bit weights too),
// then Catmull–Rom read with texelFetch (4^D fetches; its search may settle on linear
// texel-fetch, 2^D). When more than one scheme fits N, a first pass holds every scheme to
// kCompactValueBytes and a second to B. The searches share their bakes: a grid baked once is not
// baked again, and a hardware-filtered bake's texelFetch twin (the full-precision lookup alone
// validated, tables/bake.h) is the texelFetch scheme's table of that grid.
#pragma once

#include <cstdint>
#include <string>

#include "models/model.h"
#include "tables/bake.h"
#include "tables/table.h"
#include "util/error.h"

namespace ganzfeld::tables {

/// Default cap of --max-bytes (value bytes, what a shader uploads).
inline constexpr std::uint64_t kDefaultMaxValueBytes = std::uint64_t{64} << 20;  // 64 MiB
/// Node cubature tolerance = E / this; reference tolerance of the validation = E / the other.
inline constexpr double kNodeToleranceRatio = 100.0;
inline constexpr double kCheckToleranceRatio = 1000.0;
/// Random validation points of a --max-error bake (besides the cell centres).
inline constexpr std::uint64_t kSearchChecks = 2000;
inline constexpr int kMaxSearchBakes = 6;
/// A fetch-budgeted search with several schemes within its budget first holds each to this many
/// value bytes (the size the project's tables aim at: docs/tradeoff.md), then to the cap.
inline constexpr std::uint64_t kCompactValueBytes = 256000;
/// A predicted table at most this many times the byte cap is shrunk to fit it and baked (the
/// best the search can still do); one further over it ends the search.
inline constexpr double kCapFitReach = 8.0;

/// The smallest E an encoding can hold: twice its unit roundoff at 1 (laws are of order 1), so
/// that storage rounding alone never uses more than half of E. float: 2^-23; half: 2^-10;
/// unorm16: 1/65535 (a code step of a table whose values span [0, 1]; a wider range rounds
/// more, and the bake's node error, which includes the rounding, says so).
double min_max_error(Encoding encoding) noexcept;

/// Refuses (InputError, one line) E that is not a finite number above min_max_error(encoding)
/// and B below the smallest table (4 nodes per axis).
void check_error_target(double max_error, std::uint64_t max_bytes, Law law, Encoding encoding);
/// Refuses a fetch budget below 1 ("--fetches N is not allowed; expected an integer >= 1").
void check_fetch_budget(long long fetches);
/// The refusal of `parameter`, a part of an error target (max_bytes, fetches or best_effort),
/// given without max_error, in one wording for every front end: "fetches needs max_error (it is
/// the fetch budget of that search)".
InputError needs_target(const std::string& parameter);

/// The table of law `law` of `model` with lookup_error <= request.target.lookup_error and
/// value_bytes <= request.target.max_bytes (0: kDefaultMaxValueBytes), within its fetch budget,
/// baked as described above: resolution, mappings, frame, interpolation, filter, tolerance,
/// random_checks and check_tolerance are chosen here. Throws InputError "cannot reach ... within
/// ... bytes; the best ... is ..." when it cannot, unless request.target.best_effort: then the
/// most accurate table the search baked, target unmet.
Table bake_to_error(const Model& model, Law law, const TargetBake& request);

}  // namespace ganzfeld::tables
