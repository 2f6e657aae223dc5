// Internal to src/scene: the PLY header (format, elements, typed properties) and the value types it names, parsed
// for ply_reader.cpp, which reads the data the header describes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rayaccel::ply {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };
enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

/// The type a header names ("uchar" or "uint8", ...), or nothing for an unknown name.
std::optional<PlyType> parse_type(std::string_view name);
/// The type's name in messages ("uchar", "float", ...).
const char* type_name(PlyType t);
/// Bytes per binary value.
std::size_t type_size(PlyType t);
bool is_integer(PlyType t);
/// The range of an integer type.
void integer_range(PlyType t, double& lo, double& hi);

struct Property {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::uint8;  ///< lists only
  PlyType type = PlyType::float32;      ///< the value type, or a list's item type
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  std::size_t line = 0;  ///< header line that declares it
};

struct Header {
  PlyFormat format = PlyFormat::ascii;
  std::vector<Element> elements;
  std::size_t data_offset = 0;  ///< first byte after the end_header line
  std::size_t lines = 0;        ///< lines in the header
};

/// Splits a line into whitespace-separated tokens.
std::vector<std::string_view> tokens_of(std::string_view line);

/// The header at the start of `file` (its bytes as chars); throws Error "PLY file 'NAME': ..." naming the header
/// line and what is wrong with it.
Header parse_header(std::string_view file, const std::string& name);

}  // namespace rayaccel::ply
