// ganzfeld info: a table's metadata (docs/lut-format.md).
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/registry.h"
#include "shapes/json.h"
#include "tables/bake.h"
#include "tables/exr_io.h"
#include "tables/param_table.h"

namespace ganzfeld::cli {

namespace {
struct InfoArgs {
  std::string path;
  bool json = false;
};

/// info of a format version 3 table: preset, axes with their grid, channels with definitions.
int param_info(const std::string& path, bool json) {
  const tables::ParamTable table = tables::read_param_table(path);
  const nlohmann::ordered_json axes = tables::param_axes_json(table);
  nlohmann::ordered_json channels = nlohmann::ordered_json::array();
  for (const tables::Channel& ch : table.channels) {
    const double max_error = ch.node_error();
    channels.push_back({{"name", ch.name},
                        {"definition", ch.definition},
                        {"lookup_error", ch.lookup_error},
                        {"max_error", max_error},
                        {"unconverged", ch.unconverged}});
  }
  if (json) {
    nlohmann::ordered_json doc{
        {"path", path},
        {"format_version", tables::kParamFormatVersion},
        {"preset", table.preset},
        {"layout", table.layout},
        {"model", table.model},
        {"axes", axes},
        {"channels", channels},
        {"lookup_error", table.lookup_error},
        {"lookup_checks", table.lookup_checks},
        {"validated_domain", {{"alpha_min", tables::kMinValidatedAlpha}, {"cos_theta_i_min", tables::kMinValidatedMu}}},
        {"max_error", table.node_error},
        {"tolerance", table.tolerance},
        {"encoding", to_string(table.encoding)},
        {"command", table.command},
        {"version", table.version}};
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  std::printf("%s\n  format version %d, ganzfeld %s\n  preset       %s (%s)\n  model        %s\n", path.c_str(),
              tables::kParamFormatVersion, table.version.c_str(), table.preset.c_str(), table.layout.c_str(),
              table.model.c_str());
  for (const auto& a : axes)
    std::printf("  axis         %-12s [%s, %s] %d samples, %s, %s-centred\n", a["name"].get<std::string>().c_str(),
                format_number(a["min"].get<double>()).c_str(), format_number(a["max"].get<double>()).c_str(),
                a["count"].get<int>(), a["mapping"].get<std::string>().c_str(), to_string(table.grid));
  for (const auto& c : channels)
    std::printf("  channel      %-8s lookup error %.3g (per texel %.3g), %lld unconverged: %s\n",
                c["name"].get<std::string>().c_str(), c["lookup_error"].get<double>(), c["max_error"].get<double>(),
                c["unconverged"].get<long long>(), c["definition"].get<std::string>().c_str());
  std::printf(
      "  error        %s (lookup error: validated bound of |bilinear lookup - integral| for alpha >= %s and "
      "cos_theta_i >= %s, margin x the largest measured at %lld points between the samples)\n"
      "  node error   %s (cubature + rounding at the samples only)\n"
      "  tolerance    %s\n  encoding     %s\n  command      %s\n",
      format_number(table.lookup_error).c_str(), format_number(tables::kMinValidatedAlpha).c_str(),
      format_number(tables::kMinValidatedMu).c_str(), table.lookup_checks, format_number(table.node_error).c_str(),
      format_number(table.tolerance).c_str(), to_string(table.encoding), table.command.c_str());
  return 0;
}
}  // namespace

void add_info_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("info", "metadata of a baked table (refuses files that are not valid tables)");
  auto args = std::make_shared<InfoArgs>();
  add_table_argument(*cmd, args->path);
  add_json_flag(*cmd, args->json);
  cmd->callback([&action, args] {
    action = [args] {
      if (tables::format_version_of(args->path) == tables::kParamFormatVersion)
        return param_info(args->path, args->json);
      const tables::Table table = tables::read_table(args->path);
      if (args->json) {
        std::cout << shapes::info_json(args->path, table).dump(2) << "\n";
        return 0;
      }
      std::printf("%s\n  format version %d, ganzfeld %s\n  model        %s\n  law          %s\n", args->path.c_str(),
                  table.format_version, table.version.c_str(), table.model.c_str(), to_string(table.law));
      std::printf(
          "  error        %s (lookup error: validated bound of |lookup - law|, %s at %lld points the "
          "table was not built from)\n",
          format_number(table.lookup_error).c_str(),
          table.format_version >= 2 ? "margin x the largest measured" : "measured", table.interpolation_checks);
      if (table.target_error > 0.0)
        std::printf("  target       lookup error <= %s within %llu value bytes: %s\n",
                    format_number(table.target_error).c_str(), static_cast<unsigned long long>(table.target_bytes),
                    tables::misses_target(table) ? "missed (a best-effort bake)" : "met");
      if (table.target_fetches > 0) std::printf("  fetch budget %d per lookup\n", table.target_fetches);
      std::printf("  frame        %s%s%s, %s interpolation\n", to_string(table.frame),
                  table.frame != tables::Frame::cosines ? ", peak " : "",
                  table.frame != tables::Frame::cosines ? to_string(table.peak) : "", to_string(table.interpolation));
      std::printf("  lookup       %s: %d texture fetch%s per lookup; the error above is for this lookup%s%s\n",
                  table.filter == tables::Filter::hardware ? "hardware filter (GL_LINEAR)" : "texelFetch",
                  tables::fetches(table), tables::fetches(table) == 1 ? "" : "es",
                  table.filter == tables::Filter::hardware ? ", with 8-bit filter weights rounded or truncated" : "",
                  table.min_cos_j > 0.0 ? (", at j·n >= " + format_number(table.min_cos_j)).c_str() : "");
      if (table.frame == tables::Frame::warped)
        std::printf("  warp         %zu samples over theta_j, mix %s, envelope width %s\n", table.warp.samples.size(),
                    format_number(table.warp.mix).c_str(), format_number(table.warp.envelope).c_str());
      if (!table.model_content.empty()) std::printf("  model data   %s\n", table.model_content.c_str());
      for (const tables::Axis& a : table.axes)
        std::printf("  axis         %-12s [%s, %s] %d nodes, %s%s\n", a.name.c_str(), format_number(a.min).c_str(),
                    format_number(a.max).c_str(), a.count, to_string(a.mapping),
                    a.has_width() ? (" (width " + format_number(a.width) + ")").c_str() : "");
      const std::string unorm = table.encoding == tables::Encoding::unorm16
                                    ? " (value = " + format_number(table.unorm.offset) + " + " +
                                          format_number(table.unorm.scale) + " u / 65535)"
                                    : "";
      std::printf(
          "  encoding     %s%s, %llu value bytes\n  node error   %s (cubature + rounding at the nodes only)\n"
          "  tolerance    %s\n  unconverged  %lld of %zu\n  command      %s\n",
          to_string(table.encoding), unorm.c_str(), static_cast<unsigned long long>(tables::value_bytes(table)),
          format_number(table.node_error).c_str(), format_number(table.tolerance).c_str(), table.unconverged,
          table.entries(), table.command.c_str());
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
