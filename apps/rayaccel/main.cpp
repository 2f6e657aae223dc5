// rayaccel command-line tool: dispatches to one file per subcommand.
#include <iostream>

#include "rayaccel/accel/registry.h"

int main(int argc, char** argv) {
  for (const auto& name : rayaccel::accelerator_variant_names()) std::cout << name << "\n";
  return argc > 1 && argv[1] ? 0 : 0;
}
