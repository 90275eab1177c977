// Which tables a scene needs (design.md, "Scene file"): the laws are linear in f, so tables are
// per lobe, and the light fields decide which laws are looked up:
//   collimated light     H0 (i·n) f(i, j)   no table (f is evaluated directly)
//   hemispherical sky    N g(i, j, n)       g of every lobe of every material an object uses
//   Ganzfeld             N h(j, n)          h of every such lobe
// Lambert lobes never need a table: h = 1 and g = (1 + i·n)/2 in closed form (K&P).
// Anisotropic lobes get none either: their g would need a fourth axis (the azimuth of j from the
// tangent); renders compute their g and h directly by cubature per pixel instead.
#pragma once

#include <string>
#include <vector>

#include "integrate/laws.h"
#include "lut/scene.h"

namespace ganzfeld::lut {

/// Defaults of a scene's tables (float encoding, default mappings), shared by `bake --scene` and
/// `render` so that a cache filled by one is reused by the other.
inline constexpr int kSceneResG[3] = {32, 32, 16};
inline constexpr int kSceneResH = 128;
inline constexpr double kSceneTolerance = 1e-8;

struct TableRequest {
  std::string spec;  ///< canonical spec of a single (non-mixture) model, Model::spec()
  Law law = Law::h;  ///< g or h
  ModelPtr model;
  friend bool operator==(const TableRequest& a, const TableRequest& b) { return a.spec == b.spec && a.law == b.law; }
};

/// True when law (g or h) of the single-model `spec` has a closed form the renderer uses
/// instead of a table: only Lambert.
bool has_closed_form(const std::string& spec, Law law);

/// The tables the scene needs, deduplicated, in a deterministic order: g before h, then the
/// order of first use (materials in file order, lobes in material order). Materials no object
/// uses need nothing; a scene lit only by collimated light needs nothing.
std::vector<TableRequest> tables_needed(const Scene& scene);

}  // namespace ganzfeld::lut
