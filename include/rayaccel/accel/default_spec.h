// The spec every caller builds when none is named: the CLI's --accel, Python's build() and Accelerator(), and the
// Dask helpers all take it from here (defined by the catalog, the one place that knows every structure).
#pragma once

#include <string>

namespace rayaccel {

/// The catalog's choice: its fastest structure, a spec that make_accelerator() accepts.
std::string default_accelerator_spec();

}  // namespace rayaccel
