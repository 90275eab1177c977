// The requests of `ganzfeld serve` (docs/serve.md), parsed and validated apart from HTTP: a query
// (the decoded ?key=value pairs) becomes what the library is asked, or a RequestError whose one
// line names the bad value and what is allowed. A model naming a data file (file=NAME) is built
// only from a file of `serve --data DIR` listed under that name (serve/data.h): refused (400)
// without --data, 404 for a name not listed; no request can name a path.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "integrate/cubature.h"
#include "integrate/laws.h"
#include "models/spec.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "serve/data.h"
#include "tables/bake.h"

namespace ganzfeld::serve {

/// The decoded query parameters.
using Query = std::multimap<std::string, std::string>;

/// A refused request: 400 (bad value), 404 (no such endpoint) or 413 (more than the service
/// computes on demand); what() is one line for {"error": ...}.
class RequestError : public std::runtime_error {
 public:
  RequestError(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
  int status() const noexcept { return status_; }

 private:
  int status_;
};

/// Refuses (400) repeated parameters and parameters the endpoint does not know, naming those it knows.
void check_names(const Query& query, const std::string& endpoint, const std::vector<std::string>& allowed);
/// The parameter's text, or nothing.
std::optional<std::string> text_of(const Query& query, const std::string& name);
/// The parameter's text; 400 "missing parameter" with `example` when absent or empty.
std::string required(const Query& query, const std::string& name, const std::string& example);
/// The parameter as a finite number (all of its text), or nothing; 400 otherwise.
std::optional<double> number(const Query& query, const std::string& name);

/// The query of a request target (the text after '?'): pairs split at '&', each at its first
/// '=' (a spec's own '=' stays in the value: model=specular:alpha=8), %XX and '+' (a space)
/// decoded; a '+' inside a value is sent as %2B. A malformed escape is refused (400).
Query parse_query(std::string_view text);

/// What one request may cost.
struct Limits {
  /// Largest table baked on demand, in entries (64 x 64 x 64): larger ones are refused with 413.
  std::uint64_t max_entries = 64 * 64 * 64;
  /// Evaluation budget of one eval and of each table entry; beyond it: not converged.
  long long max_evaluations = CubatureOptions{}.max_evaluations;
  /// Most tables one scene request (GET /api/glsl?scene=...) may need; more: 413.
  std::size_t max_scene_tables = 16;
  /// Most lobes of a mixture in one request; more: 413.
  std::size_t max_lobes = 16;
};

/// The largest |phi| of /api/eval, in degrees (a whole turn either way).
inline constexpr double kMaxPhi = 360.0;

/// GET /api/eval?model=SPEC&law=f|g|h|a|r&theta_i=DEG&theta_j=DEG&phi=DEG&tol=T
struct EvalQuery {
  ModelPtr model;
  Law law = Law::f;
  std::optional<Vec3> i, j;  ///< set when the law uses them
  double tolerance = 1e-9;
  CubatureOptions options;
};
EvalQuery parse_eval(const Query& query, const Limits& limits, const DataFiles& data = {});

enum class TableFormat { exr, ktx2, json };
const char* to_string(TableFormat format);     ///< "exr", "ktx2", "json"
const char* content_type(TableFormat format);  ///< the media type of the body

/// GET /api/table?model=SPEC&law=g|h|a[&res=N[xNxN]][&tol=T][&encoding=float|half][&format=exr|ktx2|json]
/// and GET /api/glsl with the same parameters but format: with res or tol, a fixed grid
/// (tables::BakeOptions); with max_error=E[&fetches=N] instead, a strict error target
/// (tables::TargetBake); with neither, what `defaults` asks for (scene::TableOptions: the scene
/// defaults' best-effort target), so a service answers from the cache entries `bake scene`,
/// `render` and `export-glsl --scene` fill, and fills entries they reuse. Unset grid parameters
/// take the grid of `defaults`.
struct TableQuery {
  ModelPtr model;
  Law law = Law::g;
  tables::BakeRequest options;
  TableFormat format = TableFormat::exr;
  std::string key;        ///< tables::key_text of the table: one bake per key (serve/bakery.h)
  std::string file_name;  ///< tables::cache_file_name: the only file the request can reach
};
enum class TableEndpoint { table, glsl };
TableQuery parse_table(const Query& query, const Limits& limits, TableEndpoint endpoint,
                       const scene::TableOptions& defaults = {}, const DataFiles& data = {});

/// The TableQuery of law `law` of `model` baked with `options` (key and cache file name set);
/// throws RequestError 400 for axes a bake would refuse.
TableQuery table_query(ModelPtr model, Law law, tables::BakeRequest options, TableFormat format = TableFormat::exr);

/// GET /api/glsl?scene=SCENE[&format=glsl|json]: SCENE is the text of a scene file
/// (examples/default.json; its meshes are never read: the shader does not need them). Refused (400):
/// a malformed scene, a lobe naming a data file, a scene export-glsl refuses.
struct SceneQuery {
  Scene scene;
  bool json = false;  ///< format=json: {"glsl", "textures": [...]}; else the shader as text
};
SceneQuery parse_scene_glsl(const Query& query);

/// GET /api/glsl?model=SPEC&law=f: f in closed form as GLSL (exporting::glsl_model_f), no table;
/// the viewer's collimated beam. is_f_glsl: the /api/glsl query asks for law f.
bool is_f_glsl(const Query& query);
ModelPtr parse_f_glsl(const Query& query, const Limits& limits = {}, const DataFiles& data = {});

/// A spec given in a request, parsed (unknown model or parameter: 400 with the parser's
/// message), its file=NAME items resolved by `data` (400 naming a data file without --data, 404
/// for a name not listed: serve/data.h), refused (413) when it is a mixture of more than
/// limits.max_lobes lobes, and its model built.
struct SpecQuery {
  Spec spec;
  ModelPtr model;
};
SpecQuery parse_served_spec(const std::string& text, const Limits& limits = {}, const DataFiles& data = {});
/// parse_served_spec(spec, limits, data).model.
ModelPtr parse_served_model(const std::string& spec, const Limits& limits = {}, const DataFiles& data = {});

/// GET /api/spec?model=SPEC: the spec as the service parses it.
SpecQuery parse_spec_query(const Query& query, const Limits& limits = {}, const DataFiles& data = {});

}  // namespace ganzfeld::serve
