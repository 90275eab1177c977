// The JSON documents ganzfeld writes, built in one place so that the command line
// (`models --json`, `eval --json`, `info --json`, `bake --json`) and the service (serve/:
// /api/models, /api/eval, /api/table) answer with the same shapes.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "integrate/laws.h"
#include "models/spec.h"
#include "tables/cache.h"
#include "tables/table.h"

namespace ganzfeld::shapes {

/// The registry: {"models": [{name, summary, source, example, parameters, isotropic, reciprocal,
/// energy_class, closed_forms}], "mixtures": "..."}; a parameter is {name, type, min, max,
/// default, meaning, [choices], [min_exclusive], [optional], allowed} or, for a data file,
/// {name: "file", type: "path", required, meaning}.
nlohmann::ordered_json models_json();

/// A parsed spec (models/spec.h) and its model's canonical text: {canonical, terms: [{weight,
/// model, parameters: {KEY: VALUE}, [file]}]}; the parameters as the spec gives them, in the
/// registry's order, a choice by name.
nlohmann::ordered_json spec_json(const Spec& spec, const std::string& canonical);

/// One value of a law: {model, law, value, error, evaluations, converged, tolerance, [i], [j],
/// seconds}; i and j only when the law uses them.
nlohmann::ordered_json eval_json(const std::string& spec, Law law, const Estimate& estimate, double tolerance,
                                 const std::optional<Vec3>& i, const std::optional<Vec3>& j, double seconds);

/// A table as `bake --json` lists it: {path (null in memory), model, law, status, entries,
/// max_error, unconverged, seconds}.
nlohmann::ordered_json table_json(const std::string& path, const tables::Table& table, tables::CacheStatus status,
                                  double seconds);

/// A table's metadata as `info --json` prints it: {path, format_version, model, model_content,
/// law, axes: [{name, min, max, count, mapping}], entries, tolerance, max_error, unconverged,
/// interpolation_error, interpolation_checks, encoding, command, version}.
nlohmann::ordered_json info_json(const std::string& path, const tables::Table& table);

}  // namespace ganzfeld::shapes
