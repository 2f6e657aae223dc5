// The parameter set of the generalized-ray conformance suites: every registered variant with beam and cone
// traversals (supports_generalized_rays()), so a structure that gains them is tested without editing a list.
#pragma once

#include <string>
#include <vector>

#include "../conformance/oracle.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/generalized/generalized_rays.h"

namespace rayaccel::testing {

inline const std::vector<std::string>& generalized_specs() {
  static const std::vector<std::string> specs = [] {
    std::vector<std::string> out;
    for (const std::string& spec : conformance::variant_specs()) {
      if (generalized::supports_generalized_rays(*make_accelerator(spec))) out.push_back(spec);
    }
    return out;
  }();
  return specs;
}

}  // namespace rayaccel::testing
