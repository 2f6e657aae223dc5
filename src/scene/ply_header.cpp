// The PLY header parser (ply_header.h): the lines up to end_header read into elements and their typed properties.
#include "ply_header.h"

#include <charconv>

#include "rayaccel/core/error.h"

namespace rayaccel::ply {

std::optional<PlyType> parse_type(std::string_view name) {
  if (name == "char" || name == "int8") return PlyType::int8;
  if (name == "uchar" || name == "uint8") return PlyType::uint8;
  if (name == "short" || name == "int16") return PlyType::int16;
  if (name == "ushort" || name == "uint16") return PlyType::uint16;
  if (name == "int" || name == "int32") return PlyType::int32;
  if (name == "uint" || name == "uint32") return PlyType::uint32;
  if (name == "float" || name == "float32") return PlyType::float32;
  if (name == "double" || name == "float64") return PlyType::float64;
  return std::nullopt;
}

const char* type_name(PlyType t) {
  switch (t) {
    case PlyType::int8: return "char";
    case PlyType::uint8: return "uchar";
    case PlyType::int16: return "short";
    case PlyType::uint16: return "ushort";
    case PlyType::int32: return "int";
    case PlyType::uint32: return "uint";
    case PlyType::float32: return "float";
    case PlyType::float64: return "double";
  }
  return "?";
}

std::size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::int8: case PlyType::uint8: return 1;
    case PlyType::int16: case PlyType::uint16: return 2;
    case PlyType::int32: case PlyType::uint32: case PlyType::float32: return 4;
    case PlyType::float64: return 8;
  }
  return 1;
}

bool is_integer(PlyType t) { return t != PlyType::float32 && t != PlyType::float64; }

/// The range of an integer type.
void integer_range(PlyType t, double& lo, double& hi) {
  switch (t) {
    case PlyType::int8: lo = -128; hi = 127; return;
    case PlyType::uint8: lo = 0; hi = 255; return;
    case PlyType::int16: lo = -32768; hi = 32767; return;
    case PlyType::uint16: lo = 0; hi = 65535; return;
    case PlyType::int32: lo = -2147483648.0; hi = 2147483647.0; return;
    default: lo = 0; hi = 4294967295.0; return;
  }
}

/// Splits a line into whitespace-separated tokens.
std::vector<std::string_view> tokens_of(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw Error("PLY file '" + name + "': " + what);
}

const Element* find(const Header& header, std::string_view name) {
  for (const Element& e : header.elements) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

}  // namespace

Header parse_header(std::string_view file, const std::string& name) {
  Header header;
  std::size_t pos = 0, line = 0;
  bool have_format = false;
  for (;;) {
    const std::size_t end = file.find('\n', pos);
    if (end == std::string_view::npos) {
      if (file.substr(pos).find('\r') != std::string_view::npos) {
        fail(name, "header line " + std::to_string(line + 1) +
                         " ends in a bare CR (old Mac line endings); PLY lines end in LF or CR LF");
      }
      fail(name, file.empty() ? "empty file"
                              : "the file ends inside its header (after line " + std::to_string(line) +
                                    ", no end_header)");
    }
    std::string_view text = file.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    const std::vector<std::string_view> t = tokens_of(text);
    const std::string where = "header line " + std::to_string(line) + ": ";
    if (line == 1) {
      if (t.size() != 1 || t[0] != "ply") fail(name, "not a PLY file (the first line is not 'ply')");
      continue;
    }
    if (t.empty()) continue;
    if (t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") {
      if (!have_format) fail(name, where + "end_header before any format line");
      header.data_offset = pos;
      header.lines = line;
      return header;
    }
    if (t[0] == "format") {
      if (have_format) fail(name, where + "a second format line");
      if (t.size() != 3) fail(name, where + "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      if (t[1] == "ascii") header.format = PlyFormat::ascii;
      else if (t[1] == "binary_little_endian") header.format = PlyFormat::binary_little_endian;
      else if (t[1] == "binary_big_endian") header.format = PlyFormat::binary_big_endian;
      else fail(name, where + "unknown format '" + std::string(t[1]) + "'");
      if (t[2] != "1.0") fail(name, where + "unsupported version '" + std::string(t[2]) + "' (only 1.0)");
      have_format = true;
      continue;
    }
    if (t[0] == "element") {
      if (t.size() != 3) fail(name, where + "expected 'element NAME COUNT'");
      Element e;
      e.name = std::string(t[1]);
      e.line = line;
      const auto [ptr, ec] = std::from_chars(t[2].data(), t[2].data() + t[2].size(), e.count);
      if (ec != std::errc() || ptr != t[2].data() + t[2].size()) {
        fail(name, where + "element '" + e.name + "' count '" + std::string(t[2]) + "' is not a non-negative integer");
      }
      if (find(header, e.name)) fail(name, where + "a second element named '" + e.name + "'");
      header.elements.push_back(std::move(e));
      continue;
    }
    if (t[0] == "property") {
      if (header.elements.empty()) fail(name, where + "a property before any element");
      Property p;
      if (t.size() == 5 && t[1] == "list") {
        p.is_list = true;
        const auto count_type = parse_type(t[2]), item_type = parse_type(t[3]);
        if (!count_type || !item_type) fail(name, where + "unknown type in '" + std::string(text) + "'");
        if (!is_integer(*count_type)) {
          fail(name, where + "a list count of type '" + std::string(t[2]) + "' (not an integer)");
        }
        p.count_type = *count_type;
        p.type = *item_type;
        p.name = std::string(t[4]);
      } else if (t.size() == 3) {
        const auto type = parse_type(t[1]);
        if (!type) fail(name, where + "unknown type '" + std::string(t[1]) + "'");
        p.type = *type;
        p.name = std::string(t[2]);
      } else {
        fail(name, where + "expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'");
      }
      header.elements.back().properties.push_back(std::move(p));
      continue;
    }
    fail(name, where + "unknown header keyword '" + std::string(t[0]) + "'");
  }
}

}  // namespace rayaccel::ply
