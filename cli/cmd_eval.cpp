#include <cstdio>
#include <iostream>

#include "cli/args.h"
#include "cli/commands.h"
#include "models/spec.h"
#include "shapes/json.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::cli {

namespace {
struct EvalArgs {
  std::string model, law;
  DirectionArgs directions;
  ParameterArgs parameter;
  double tol = 1e-9;
  long long max_evaluations = CubatureOptions{}.max_evaluations;
  bool json = false;
};
}  // namespace

void add_eval_command(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("eval", "one value of a law (f, g, h, a, r) with its error estimate");
  auto args = std::make_shared<EvalArgs>();
  add_model_option(*cmd, args->model);
  cmd->add_option("--law", args->law, "f (BRDF), g (vignetting), h (darkening), a (albedo), r (double-diffuse)")
      ->required();
  args->directions.add_to(*cmd);
  args->parameter.add_to(*cmd);
  cmd->add_option("--tol", args->tol, "absolute tolerance of the cubature (default 1e-9)");
  cmd->add_option("--max-evals", args->max_evaluations,
                  "evaluation budget; beyond it the result is reported as not converged");
  add_json_flag(*cmd, args->json);
  cmd->callback([&action, args] {
    action = [args] {
      const Law law = parse_law(args->law);
      const auto parameter = args->parameter.given();
      const ModelPtr model =
          parameter ? make_model(with_parameter(parse_spec(args->model), parameter->first, parameter->second))
                    : parse_model(args->model);
      validate_tolerance(args->tol);
      check_max_evaluations(args->max_evaluations);
      const bool needs_i = law == Law::f || law == Law::g || law == Law::a;
      const bool needs_j = law == Law::f || law == Law::g || law == Law::h;
      const Vec3 i = needs_i ? args->directions.incident(law) : Vec3{0, 0, 1};
      const Vec3 j = needs_j ? args->directions.outgoing(law) : Vec3{0, 0, 1};
      CubatureOptions options;
      options.abs_tol = args->tol;
      options.max_evaluations = args->max_evaluations;
      const util::Stopwatch watch;
      const Estimate e = evaluate_law(*model, law, i, j, options);
      const double seconds = watch.seconds();
      if (args->json) {
        std::cout << shapes::eval_json(model->spec(), law, e, args->tol, needs_i ? std::optional(i) : std::nullopt,
                                       needs_j ? std::optional(j) : std::nullopt, seconds)
                         .dump(2)
                  << "\n";
      } else {
        std::printf("%s %s = %.17g ± %.2g (%lld evaluations, %s, %.3f s)\n", model->spec().c_str(), to_string(law),
                    e.value, e.error, e.evaluations, e.converged ? "converged" : "NOT converged", seconds);
      }
      if (!e.converged)
        std::cerr << "ganzfeld: warning: tolerance " << args->tol << " not reached within " << args->max_evaluations
                  << " evaluations; the error estimate above is what was achieved\n";
      return 0;
    };
  });
}

}  // namespace ganzfeld::cli
