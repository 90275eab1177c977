// ganzfeld._core: the library's models, laws, tables and reports for the Python package
// python/ganzfeld/ (docs/python.md), which broadcasts and checks the arguments and calls these.
// Directions cross as contiguous (N, 3) float64 arrays, results as numpy arrays. Long work runs
// on a thread of its own with the GIL released (run_released) while the calling thread answers
// Ctrl-C and reports progress. Bad input raises ValueError with the library's one-line message,
// the one `ganzfeld` prints after "ganzfeld: ".
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "batch.h"
#include "integrate/laws.h"
#include "models/spec.h"
#include "reports/verify.h"
#include "shapes/json.h"
#include "tables/bake.h"
#include "tables/exr_io.h"
#include "tables/frame.h"
#include "tables/sample.h"
#include "tables/table.h"
#include "tables/to_error.h"
#include "util/error.h"
#include "util/progress.h"

namespace py = pybind11;

namespace ganzfeld::python {
namespace {

/// How often the waiting thread looks for Ctrl-C and reports progress.
constexpr std::chrono::milliseconds kPoll{50};

/// Thrown inside a bake (from its progress callback) once the caller has cancelled it.
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

/// Runs `work` on a thread of its own with the GIL released. Every kPoll the calling thread takes
/// the GIL, checks for signals (PyErr_CheckSignals: Ctrl-C raises KeyboardInterrupt there) and
/// calls progress(done, total) when `done` moved (progress: a Python callable or None). A signal
/// or an exception from `progress` sets control.cancel; `work` is awaited, then that exception is
/// raised. An exception from `work` itself is rethrown.
void run_released(BatchControl& control, const std::atomic<std::uint64_t>& total, const py::object& progress,
                  const std::function<void()>& work) {
  std::exception_ptr failure, interruption;
  std::uint64_t reported = 0;
  auto report = [&] {
    const std::uint64_t done = control.done.load();
    if (progress.is_none() || done == reported) return;
    reported = done;
    progress(done, total.load());
  };
  {
    py::gil_scoped_release release;
    std::mutex mutex;
    std::condition_variable finished_signal;
    bool finished = false;
    std::thread worker([&] {
      try {
        work();
      } catch (...) { failure = std::current_exception(); }
      const std::lock_guard lock(mutex);
      finished = true;
      finished_signal.notify_one();
    });
    for (;;) {
      {
        std::unique_lock lock(mutex);
        if (finished_signal.wait_for(lock, kPoll, [&] { return finished; })) break;
      }
      if (interruption) continue;  // cancelled: the workers are finishing the entries they started
      const py::gil_scoped_acquire acquire;
      try {
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        report();
      } catch (...) {
        interruption = std::current_exception();
        control.cancel = true;
      }
    }
    worker.join();
  }
  if (interruption) std::rethrow_exception(interruption);
  if (failure) std::rethrow_exception(failure);
  report();
}

/// The rows of a contiguous (N, 3) array as vectors (the package has checked the shape).
std::vector<Vec3> vectors(const py::array_t<double, py::array::c_style | py::array::forcecast>& rows) {
  if (rows.ndim() != 2 || rows.shape(1) != 3) throw InputError("expected an array of shape (N, 3)");
  const auto r = rows.unchecked<2>();
  std::vector<Vec3> out(static_cast<std::size_t>(r.shape(0)));
  for (py::ssize_t m = 0; m < r.shape(0); ++m) out[m] = Vec3{r(m, 0), r(m, 1), r(m, 2)};
  return out;
}

py::array_t<double> rows_of(const std::vector<Vec3>& v) {
  py::array_t<double> out({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
  auto o = out.mutable_unchecked<2>();
  for (std::size_t m = 0; m < v.size(); ++m)
    for (int c = 0; c < 3; ++c) o(m, c) = v[m][c];
  return out;
}

/// d / |d| row by row, as `ganzfeld eval` normalizes --i and --j (cli/args.cpp, parse_vector),
/// so that the same numbers give the same bits.
py::array_t<double> unit(const py::array_t<double, py::array::c_style | py::array::forcecast>& rows) {
  std::vector<Vec3> v = vectors(rows);
  for (Vec3& d : v) d = d / glm::length(d);
  return rows_of(v);
}

/// Unit directions of polar angles theta in degrees (`polar_in_degrees`, converted as `ganzfeld
/// eval` converts --theta-i/--theta-j/--phi: direction(theta pi/180, phi pi/180)) or of cos theta
/// (direction_from_cos, exact at 0 and ±1), and azimuths phi in degrees.
py::array_t<double> directions(const py::array_t<double, py::array::c_style | py::array::forcecast>& polar,
                               const py::array_t<double, py::array::c_style | py::array::forcecast>& phi,
                               bool polar_in_degrees) {
  if (polar.ndim() != 1 || phi.ndim() != 1 || polar.shape(0) != phi.shape(0))
    throw InputError("expected two arrays of shape (N,)");
  using std::numbers::pi;
  std::vector<Vec3> out(static_cast<std::size_t>(polar.shape(0)));
  for (std::size_t m = 0; m < out.size(); ++m)
    out[m] = polar_in_degrees ? direction(polar.at(m) * pi / 180.0, phi.at(m) * pi / 180.0)
                              : direction_from_cos(polar.at(m), phi.at(m) * pi / 180.0);
  return rows_of(out);
}

py::object json_to_python(const nlohmann::ordered_json& doc) {
  return py::module_::import("json").attr("loads")(doc.dump());
}

/// A model as the Python package holds it (pybind11 holders cannot be shared_ptr<const T>).
struct PyModel {
  ModelPtr model;
};

/// law(i[m], j[m]) for every row: (value, error, evaluations, converged) arrays of length N.
py::tuple evaluate(const PyModel& self, const std::string& law_name, const py::array_t<double>& i_rows,
                   const py::array_t<double>& j_rows, double tol, long long max_evaluations,
                   const py::object& progress) {
  const Law law = parse_law(law_name);
  check_tolerance("tol", tol);
  check_max_evaluations("max_evals", max_evaluations);
  const std::vector<Vec3> i = vectors(i_rows), j = vectors(j_rows);
  if (i.size() != j.size()) throw InputError("i and j hold different numbers of directions");
  CubatureOptions options;
  options.abs_tol = tol;
  options.max_evaluations = max_evaluations;
  std::vector<Estimate> out(i.size());
  BatchControl control;
  const std::atomic<std::uint64_t> total{out.size()};
  run_released(control, total, progress, [&] { evaluate_batch(*self.model, law, i, j, options, out, control); });
  const auto n = static_cast<py::ssize_t>(out.size());
  py::array_t<double> value(n), error(n);
  py::array_t<std::int64_t> evaluations(n);
  py::array_t<bool> converged(n);
  auto v = value.mutable_unchecked<1>();
  auto e = error.mutable_unchecked<1>();
  auto c = evaluations.mutable_unchecked<1>();
  auto ok = converged.mutable_unchecked<1>();
  for (py::ssize_t m = 0; m < n; ++m) {
    v(m) = out[m].value;
    e(m) = out[m].error;
    c(m) = out[m].evaluations;
    ok(m) = out[m].converged;
  }
  return py::make_tuple(value, error, evaluations, converged);
}

/// A table and the file it was read from or last written to ("" in memory).
struct PyTable {
  std::shared_ptr<tables::Table> table;
  std::string path;
};

/// A read-only numpy view of one channel, shaped by the axes (slowest first), that keeps the
/// table alive.
py::array channel(const PyTable& self, const std::vector<float>& data) {
  std::vector<py::ssize_t> shape;
  for (const tables::Axis& a : self.table->axes) shape.push_back(a.count);
  py::array out(py::dtype::of<float>(), shape, {}, data.data(), py::cast(self));
  py::detail::array_proxy(out.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return out;
}

/// The table's lookup at every row: (value, node_error) arrays (tables/sample.h).
py::tuple sample(const PyTable& self, const py::array_t<double>& i_rows, const py::array_t<double>& j_rows) {
  const std::vector<Vec3> i = vectors(i_rows), j = vectors(j_rows);
  if (i.size() != j.size()) throw InputError("i and j hold different numbers of directions");
  const auto n = static_cast<py::ssize_t>(i.size());
  py::array_t<double> value(n), node_error(n);
  auto v = value.mutable_unchecked<1>();
  auto e = node_error.mutable_unchecked<1>();
  {
    const py::gil_scoped_release release;
    for (py::ssize_t m = 0; m < n; ++m) {
      const tables::Sample s = tables::sample(*self.table, i[m], j[m]);
      v(m) = s.value;
      e(m) = s.error;
    }
  }
  return py::make_tuple(value, node_error);
}

/// The options of `ganzfeld bake model` (cli/cmd_bake.cpp), by keyword; the package has
/// turned tuples into the command line's texts.
struct BakeArguments {
  std::optional<std::string> res, mapping, frame, interpolation;
  std::optional<double> max_error;
  std::optional<std::uint64_t> max_bytes, checks;
  double tol = 1e-9;
  long long max_evaluations = CubatureOptions{}.max_evaluations;
  std::string encoding = "float";
};

/// The request of `bake`: an error target with max_error=, else a fixed grid (res= and the grid's
/// keywords); one kind's keywords are refused with the other's.
tables::BakeRequest bake_request(const Model& model, Law law, const BakeArguments& a) {
  if (!a.res && !a.max_error) throw InputError("bake needs res= (node counts) or max_error= (a lookup error)");
  if (a.res && a.max_error)
    throw InputError("res= and max_error= are mutually exclusive: max_error= chooses the resolution itself");
  if (a.max_bytes && !a.max_error)  // spelled as this module spells keywords: max_bytes=
    throw InputError(tables::needs_target("max_bytes").worded([](const Named& n) { return n.parameter + "="; }));
  check_tolerance("tol", a.tol);
  check_max_evaluations("max_evals", a.max_evaluations);
  const tables::Encoding encoding = tables::parse_encoding(a.encoding);
  if (a.max_error) {
    for (const auto& [name, set] : {std::pair{"mapping=", a.mapping.has_value()},
                                    {"frame=", a.frame.has_value()},
                                    {"interpolation=", a.interpolation.has_value()},
                                    {"checks=", a.checks.has_value()}})
      if (set) throw InputError(std::string(name) + " cannot be combined with max_error=, which chooses it itself");
    tables::TargetBake bake;
    bake.max_evaluations = a.max_evaluations;
    bake.encoding = encoding;
    bake.target.lookup_error = *a.max_error;
    bake.target.max_bytes = a.max_bytes.value_or(0);
    tables::check_error_target(bake.target.lookup_error, bake.target.max_bytes, law, encoding);
    return bake;
  }
  tables::BakeOptions options;
  options.tolerance = a.tol;
  options.max_evaluations = a.max_evaluations;
  options.encoding = encoding;
  options.resolution = tables::parse_resolution(*a.res, law);
  if (a.mapping) options.mappings = tables::parse_mappings(*a.mapping, law);
  if (a.interpolation) options.interpolation = tables::parse_interpolation(*a.interpolation);
  if (a.frame && tables::parse_frame(*a.frame) == tables::Frame::lobe) {
    if (law != Law::g) throw InputError("frame='lobe' is for law g; h and a tables use the cosines frame");
    options.lobe = tables::lobe_frame_of(model);
    if (!options.lobe)
      throw InputError("frame='lobe': model '" + model.spec() +
                       "' hints no lobe at the mirror direction or at j to follow; use frame='cosines'");
  }
  if (a.checks) options.random_checks = *a.checks;
  return options;
}

PyTable bake(const PyModel& model, const std::string& law_name, const BakeArguments& arguments,
             const std::string& command, const py::object& progress) {
  const Law law = tables::parse_tabulated_law("law", law_name);
  tables::BakeRequest request = bake_request(*model.model, law, arguments);
  BatchControl control;
  std::atomic<std::uint64_t> total{0};
  tables::common(request).progress = [&](std::uint64_t done, std::uint64_t of) {
    if (control.cancel) throw Cancelled();
    total = of;
    control.done = done;
  };
  auto table = std::make_shared<tables::Table>();
  run_released(control, total, progress, [&] { *table = tables::bake(*model.model, law, request); });
  table->command = command;
  return {table, ""};
}

}  // namespace
}  // namespace ganzfeld::python

PYBIND11_MODULE(_core, m) {
  using namespace ganzfeld;
  using namespace ganzfeld::python;
  m.doc() = "The C++ core of the ganzfeld package (import ganzfeld; docs/python.md).";
  m.attr("__version__") = GANZFELD_VERSION;
  m.attr("DEFAULT_TOL") = CubatureOptions{}.abs_tol;
  m.attr("DEFAULT_MAX_EVALS") = CubatureOptions{}.max_evaluations;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) { PyErr_SetString(PyExc_ValueError, e.what()); }
  });

  m.def(
      "models_json", [] { return json_to_python(shapes::models_json()); },
      "The registry as `ganzfeld models --json` prints it (shapes/json.h).");
  m.def(
      "verify_json",
      [] {
        BatchControl control;
        const std::atomic<std::uint64_t> total{0};
        nlohmann::ordered_json doc;
        run_released(control, total, py::none(), [&] { doc = verify_json(run_verification()); });
        return json_to_python(doc);
      },
      "The closed-form report as `ganzfeld verify --json` prints it (reports/verify.h).");
  m.def(
      "progress_bar", [](const std::string& label) { return util::progress_bar(label); },
      "The command line's progress bar on stderr (util/progress.h); None when stderr is not a terminal.");
  m.def("unit", &unit, "Rows divided by their length, as `ganzfeld eval` normalizes --i/--j.");
  m.def("directions", &directions, py::arg("polar"), py::arg("phi"), py::arg("polar_in_degrees"),
        "Unit directions of polar angles in degrees (or their cosines) and azimuths in degrees.");

  py::class_<PyModel>(m, "Model")
      .def(py::init([](const std::string& spec) { return PyModel{parse_model(spec)}; }), py::arg("spec"))
      .def_property_readonly("spec", [](const PyModel& self) { return self.model->spec(); })
      .def_property_readonly("content_digest", [](const PyModel& self) { return self.model->content_digest(); })
      .def_property_readonly("traits",
                             [](const PyModel& self) {
                               const Traits t = self.model->traits();
                               py::dict d;
                               d["isotropic"] = t.isotropic;
                               d["reciprocal"] = t.reciprocal;
                               d["energy_class"] = to_string(t.energy);
                               return d;
                             })
      .def("evaluate", &evaluate, py::arg("law"), py::arg("i"), py::arg("j"), py::arg("tol"), py::arg("max_evals"),
           py::arg("progress"));

  py::class_<BakeArguments>(m, "BakeArguments")
      .def(py::init<>())
      .def_readwrite("res", &BakeArguments::res)
      .def_readwrite("mapping", &BakeArguments::mapping)
      .def_readwrite("frame", &BakeArguments::frame)
      .def_readwrite("interpolation", &BakeArguments::interpolation)
      .def_readwrite("max_error", &BakeArguments::max_error)
      .def_readwrite("max_bytes", &BakeArguments::max_bytes)
      .def_readwrite("checks", &BakeArguments::checks)
      .def_readwrite("tol", &BakeArguments::tol)
      .def_readwrite("max_evals", &BakeArguments::max_evaluations)
      .def_readwrite("encoding", &BakeArguments::encoding);

  py::class_<PyTable>(m, "Table")
      .def_property_readonly("values", [](const PyTable& self) { return channel(self, self.table->value); })
      .def_property_readonly("errors", [](const PyTable& self) { return channel(self, self.table->error); })
      .def_property_readonly("law", [](const PyTable& self) { return std::string(to_string(self.table->law)); })
      .def_property_readonly("model", [](const PyTable& self) { return self.table->model; })
      .def_property_readonly("lookup_error", [](const PyTable& self) { return self.table->lookup_error; })
      .def_property_readonly("node_error", [](const PyTable& self) { return self.table->node_error; })
      .def_property_readonly("path", [](const PyTable& self) { return self.path; })
      .def_property_readonly(
          "info", [](const PyTable& self) { return json_to_python(shapes::info_json(self.path, *self.table)); })
      .def("sample", &sample, py::arg("i"), py::arg("j"))
      .def(
          "write",
          [](PyTable& self, const std::string& path) {
            {
              const py::gil_scoped_release release;
              tables::write_table(*self.table, path);
            }
            self.path = path;
          },
          py::arg("path"));

  m.def("bake", &bake, py::arg("model"), py::arg("law"), py::arg("arguments"), py::arg("command"), py::arg("progress"));
  m.def(
      "read_table",
      [](const std::string& path) {
        auto table = std::make_shared<tables::Table>();
        {
          const py::gil_scoped_release release;
          *table = tables::read_table(path);
        }
        return PyTable{table, path};
      },
      py::arg("path"));
}
