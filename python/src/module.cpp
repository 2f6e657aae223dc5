// rayaccel._core: the compiled half of the Python package (the rest is rayaccel/*.py). Maps the library's errors to
// Python exceptions and holds the thread limit (a tbb::global_control, as the CLI's --threads).
#include <pybind11/pybind11.h>
#include <tbb/global_control.h>

#include <memory>

#include "arrays.h"
#include "bindings.h"
#include "rayaccel/core/error.h"
#include "rayaccel/version.h"

namespace rayaccel::python {
namespace {

std::unique_ptr<tbb::global_control>& thread_limit() {
  static std::unique_ptr<tbb::global_control> limit;
  return limit;
}

/// Limits every build and batch to `threads` workers; 0 restores TBB's default (all cores).
void set_threads(int threads) {
  if (threads < 0) throw ValueError("threads must be >= 0 (0: all cores), not " + std::to_string(threads));
  thread_limit().reset();
  if (threads > 0) {
    thread_limit() = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                           static_cast<std::size_t>(threads));
  }
}

int threads() {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

}  // namespace

void bind_geometry(py::module_& m);  // geometry_bindings.cpp (declared here, not in bindings.h, which every file reads)
}  // namespace rayaccel::python

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  using namespace rayaccel::python;
  m.doc() = "rayaccel's compiled core; use the rayaccel package, not this module.";
  m.attr("__version__") = RAYACCEL_VERSION_STRING;

  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const FileNotFound& e) {
      PyErr_SetString(PyExc_FileNotFoundError, e.what());
    } catch (const TypeError& e) {
      PyErr_SetString(PyExc_TypeError, e.what());
    } catch (const ValueError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const rayaccel::Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  bind_scene(m);
  bind_accelerator(m);
  bind_render(m);
  bind_double(m);
  bind_instances(m);
  bind_geometry(m);
  bind_saved(m);

  m.def("set_threads", &set_threads, py::arg("threads"),
        "Limits every build and batch to this many worker threads (0: all cores, TBB's default).");
  m.def("_ray_buffer_address", [](const py::handle& rays) {
    return reinterpret_cast<std::uintptr_t>(float_rows(rays, 8, "rays").data());
  }, "Address of the float32 buffer queries read for this (N, 8) array (for the zero-copy test).");
  m.def("threads", &threads, "The number of worker threads builds and batches may use.");
  // Drops the limit before the interpreter (and TBB's own shutdown) runs, never from a static destructor.
  py::module_::import("atexit").attr("register")(py::cpp_function([] { thread_limit().reset(); }));
}
