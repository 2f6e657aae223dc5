// The glTF writer of the tests (see gltf_file.h).
#include "gltf_file.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

namespace rayaccel::testing {

namespace {

std::string base64(const unsigned char* data, std::size_t size) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < size; i += 3) {
    const std::uint32_t b0 = data[i], b1 = i + 1 < size ? data[i + 1] : 0, b2 = i + 2 < size ? data[i + 2] : 0;
    const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += digits[(triple >> 18) & 63];
    out += digits[(triple >> 12) & 63];
    out += i + 1 < size ? digits[(triple >> 6) & 63] : '=';
    out += i + 2 < size ? digits[triple & 63] : '=';
  }
  return out;
}

}  // namespace

void write_gltf(const std::filesystem::path& path, std::span<const float> positions, const std::string& roots,
                const std::string& nodes) {
  std::vector<unsigned char> bytes(positions.size_bytes());
  std::memcpy(bytes.data(), positions.data(), bytes.size());
  float lo[3] = {positions[0], positions[1], positions[2]}, hi[3] = {lo[0], lo[1], lo[2]};
  for (std::size_t i = 0; i < positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], positions[i]);
    hi[i % 3] = std::max(hi[i % 3], positions[i]);
  }
  const std::string size = std::to_string(bytes.size());
  std::ofstream(path) << R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": )" << roots << R"(}],
  "nodes": )" << nodes << R"(,
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 4}]}],
  "buffers": [{"byteLength": )" << size << R"(, "uri": "data:application/octet-stream;base64,)"
                      << base64(bytes.data(), bytes.size()) << R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": )" << size << R"(}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" << positions.size() / 3 << R"(, "type": "VEC3",
                 "min": [)" << lo[0] << ", " << lo[1] << ", " << lo[2] << R"(], "max": [)" << hi[0] << ", " << hi[1]
                      << ", " << hi[2] << R"(]}]
})";
}

}  // namespace rayaccel::testing
