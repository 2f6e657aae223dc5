// The C API's error reporting (a per-thread last message) and version.
#include <string>

#include "capi_handles.h"
#include "rayaccel/version.h"

namespace rayaccel::capi {
namespace {
thread_local std::string last_error;
}

rayaccel_status set_status(rayaccel_status status, const char* message) {
  try {
    last_error = status == RAYACCEL_OK ? "" : message;
  } catch (...) {
    last_error.clear();  // no room for the message: the code still says what failed
  }
  return status;
}

}  // namespace rayaccel::capi

extern "C" const char* rayaccel_last_error(void) { return rayaccel::capi::last_error.c_str(); }

extern "C" const char* rayaccel_version(void) { return RAYACCEL_VERSION_STRING; }
