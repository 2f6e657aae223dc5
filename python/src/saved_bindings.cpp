// Which structure a file written by Accelerator::save() holds, read from its header alone (the registry's saved_spec
// readers), without loading it: rayaccel.dask checks a structure file on the client before its workers load it.
#include <cstddef>
#include <fstream>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "rayaccel/accel/registry.h"

namespace rayaccel::python {

namespace {

std::string saved_spec(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileNotFound("saved structure '" + path + "' cannot be opened for reading");
  std::vector<std::byte> head(kSavedHeadBytes);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  std::string known;
  for (const AcceleratorInfo& info : accelerator_registry()) {
    if (!info.saved_spec) continue;
    if (std::string spec = info.saved_spec(head); !spec.empty()) return spec;
    known += (known.empty() ? "" : ", ") + info.name;
  }
  throw ValueError("saved structure '" + path + "' is not one: its header is none of " + known +
                   " (files written by accel.save())");
}

}  // namespace

void bind_saved(py::module_& m) {
  m.def("_saved_spec", &saved_spec, py::arg("path"),
        "The spec of the structure saved in path (from its header); ValueError for another file");
}

}  // namespace rayaccel::python
