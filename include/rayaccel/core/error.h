// Error: the one exception type the library throws for bad input (files, options, arguments); its message names
// the file, line, key or value at fault.
#pragma once

#include <stdexcept>
#include <string>

namespace rayaccel {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace rayaccel
