// ganzfeld sample: a table lookup at given directions (tables/sample.h).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "tables/exr_io.h"
#include "tables/param_table.h"
#include "tables/sample.h"
#include "util/error.h"

namespace ganzfeld::cli {

namespace {
struct SampleArgs {
  std::string path;
  DirectionArgs directions;
  ParameterArgs parameter;
  std::optional<double> mu;
  bool json = false;
  bool hardware_filter = false;
};

/// A parameter table (format version 3) at (--alpha | --roughness, --mu | --theta-i | --i):
/// every channel, bilinear in the table's grid convention.
int sample_param_table(const SampleArgs& args) {
  const tables::ParamTable table = tables::read_param_table(args.path);
  const auto parameter = args.parameter.given();
  if (!parameter)
    throw InputError("a parameter table needs --alpha A or --roughness R (its axis is " + table.axes[0].name + ")");
  // The point on the table's axis: R = sqrt(alpha) on a roughness axis, alpha = R^2 on an alpha axis.
  const bool same = parameter->first == table.axes[0].name;
  const double x = same ? parameter->second
                        : (parameter->first == tables::kAxisAlpha ? std::sqrt(parameter->second)
                                                                  : parameter->second * parameter->second);
  double mu = 0.0;
  if (args.mu) {
    if (args.directions.theta_i || !args.directions.i_text.empty())
      throw InputError("give either --mu or --theta-i/--i");
    if (!(*args.mu >= 0.0 && *args.mu <= 1.0))
      throw InputError("--mu=" + format_number(*args.mu) + " is not allowed; allowed: cos theta_i in [0, 1]");
    mu = *args.mu;
  } else {
    mu = args.directions.incident(Law::a).z;
  }
  nlohmann::ordered_json doc{{tables::kAxisAlpha, tables::alpha_of(table.axes[0].name, x)},
                             {"mu", mu},
                             {"channels", nlohmann::ordered_json::array()}};
  for (std::size_t c = 0; c < table.channels.size(); ++c) {
    const tables::ParamSample s = tables::sample_param(table, c, x, mu);
    doc["channels"].push_back({{"name", table.channels[c].name},
                               {"value", s.value},
                               {"error", table.channels[c].lookup_error},
                               {"node_error", s.error}});
  }
  if (args.json) {
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  std::printf("%s %s at alpha = %.9g, mu = %.9g (table %s):\n", table.preset.c_str(), table.model.c_str(),
              doc["alpha"].get<double>(), mu, args.path.c_str());
  for (const auto& c : doc["channels"])
    std::printf("  %-8s = %.9g ± %.2g (the channel's lookup error; the texels' own bound here %.2g)\n",
                c["name"].get<std::string>().c_str(), c["value"].get<double>(), c["error"].get<double>(),
                c["node_error"].get<double>());
  return 0;
}
}  // namespace

void add_sample_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "sample", "look a table up at directions (the table's interpolation in index space, clamped at the axis ends)");
  auto args = std::make_shared<SampleArgs>();
  add_table_argument(*cmd, args->path);
  args->directions.add_to(*cmd);
  args->parameter.add_to(*cmd);
  cmd->add_option("--mu", args->mu, "parameter tables: cos theta_i in [0, 1] (instead of --theta-i)");
  add_json_flag(*cmd, args->json);
  cmd->add_flag("--hardware-filter", args->hardware_filter,
                "emulate a GPU's linear filter: every blend weight of the exported shader's texture() calls "
                "rounded to a multiple of 1/256 (8-bit sub-texel precision, as Direct3D and Vulkan guarantee)");
  cmd->callback([&action, args] {
    action = [args] {
      if (tables::format_version_of(args->path) == tables::kParamFormatVersion) {
        if (args->hardware_filter)
          throw InputError(
              "--hardware-filter: '" + args->path +
              "' is a parameter table, whose exported lookup reads texels with texelFetch (no filtered path)");
        return sample_param_table(*args);
      }
      if (args->parameter.alpha || args->parameter.roughness || args->mu)
        throw InputError("--alpha, --roughness and --mu are for parameter tables (format version 3); '" + args->path +
                         "' is not one");
      const tables::Table table = tables::read_table(args->path);
      const Law law = table.law;
      const bool needs_i = law == Law::g || law == Law::a;
      const bool needs_j = law == Law::g || law == Law::h;
      const Vec3 i = needs_i ? args->directions.incident(law) : Vec3{0, 0, 1};
      const Vec3 j = needs_j ? args->directions.outgoing(law) : Vec3{0, 0, 1};
      if (args->hardware_filter && table.interpolation != tables::Interpolation::linear &&
          table.interpolation != tables::Interpolation::catmull_rom &&
          table.interpolation != tables::Interpolation::bspline)
        throw InputError("--hardware-filter: table '" + args->path + "' has no filtered lookup");
      const tables::WeightRounding rounding =
          args->hardware_filter ? tables::WeightRounding::nearest : tables::WeightRounding::exact;
      const tables::Sample s = tables::sample(table, i, j, rounding);
      if (args->json) {
        // error: the table's validated lookup error (docs/lut-format.md, "The error a lookup reports").
        nlohmann::ordered_json doc{
            {"value", s.value},
            {"error", table.lookup_error},
            {"node_error", s.error},
            {"validation_points", table.interpolation_checks},
            {"lookup", args->hardware_filter ? "hardware-filter emulation (8-bit weights, nearest)" : "full precision"},
            {"bound_filter", to_string(table.filter)},
            {"min_cos_theta_j", table.min_cos_j}};
        std::cout << doc.dump(2) << "\n";
      } else {
        std::printf(
            "%s %s = %.9g ± %.2g (the table's lookup error, validated at %lld points%s for the %s lookup; "
            "%s here; node error here %.2g; table %s)\n",
            table.model.c_str(), to_string(law), s.value, table.lookup_error, table.interpolation_checks,
            table.min_cos_j > 0.0 ? (" with j·n >= " + format_number(table.min_cos_j)).c_str() : "",
            to_string(table.filter), args->hardware_filter ? "8-bit filter weights emulated" : "full precision",
            s.error, args->path.c_str());
      }
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
