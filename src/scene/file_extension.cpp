// A file name's extension in lower case (file_extension.h).
#include "rayaccel/scene/file_extension.h"

#include <cctype>

namespace rayaccel {

std::string lowercase_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace rayaccel
