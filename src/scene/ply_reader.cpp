// The PLY reader (see ply_reader.h): the header parsed into elements and properties, then the data read element by
// element through one value reader per format (ASCII: one element per line; binary: fixed-size values of either
// byte order), every count checked against the bytes left before it is trusted. One parser for both meshes: vertex
// coordinates are read as double and stored in the mesh's own precision (float for TriangleMesh, kept as read for
// the double path's TriangleMeshD).
#include "rayaccel/scene/ply_reader.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/core/mesh_d.h"
#include "rayaccel/scene/file_extension.h"

namespace rayaccel {

namespace {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };
enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

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

/// The PLY text of the file, for line-based parsing (bytes as chars).
std::string_view as_text(std::span<const std::byte> bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

/// Mesh: TriangleMesh (coordinates rounded to float) or TriangleMeshD (kept in double).
template <class Mesh>
class PlyParser {
 public:
  PlyParser(std::span<const std::byte> bytes, const std::string& name) : bytes_(bytes), text_(as_text(bytes)), name_(name) {}

  Mesh parse() {
    parse_header();
    pos_ = header_.data_offset;
    line_ = header_.lines;
    const Element* vertex = find("vertex");
    if (!vertex) fail("the header declares no 'vertex' element");
    if (vertex->count > std::numeric_limits<std::uint32_t>::max()) {
      fail(header_line(*vertex) + "vertex count " + std::to_string(vertex->count) + " exceeds 2^32 - 1");
    }
    vertex_count_ = vertex->count;
    for (const Element& e : header_.elements) read_element(e);
    if (header_.format == PlyFormat::ascii) {
      for (;;) {
        const std::optional<std::string_view> extra = next_data_line();
        if (!extra) break;
        fail(at_line() + "data after the last element: '" + std::string(extra->substr(0, 40)) + "'");
      }
    }
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error("PLY file '" + name_ + "': " + what); }

  std::string header_line(const Element& e) const { return "header line " + std::to_string(e.line) + ": "; }
  std::string at_line() const { return "line " + std::to_string(line_) + ": "; }

  const Element* find(std::string_view name) const {
    for (const Element& e : header_.elements) {
      if (e.name == name) return &e;
    }
    return nullptr;
  }

  // ---- Header -------------------------------------------------------------------------------------------------

  void parse_header() {
    std::size_t pos = 0, line = 0;
    bool have_format = false;
    for (;;) {
      const std::size_t end = text_.find('\n', pos);
      if (end == std::string_view::npos) {
        if (text_.substr(pos).find('\r') != std::string_view::npos) {
          fail("header line " + std::to_string(line + 1) + " ends in a bare CR (old Mac line endings); PLY lines end "
               "in LF or CR LF");
        }
        fail(text_.empty() ? "empty file"
                           : "the file ends inside its header (after line " + std::to_string(line) +
                                 ", no end_header)");
      }
      std::string_view text = text_.substr(pos, end - pos);
      pos = end + 1;
      ++line;
      const std::vector<std::string_view> t = tokens_of(text);
      const std::string where = "header line " + std::to_string(line) + ": ";
      if (line == 1) {
        if (t.size() != 1 || t[0] != "ply") fail("not a PLY file (the first line is not 'ply')");
        continue;
      }
      if (t.empty()) continue;
      if (t[0] == "comment" || t[0] == "obj_info") continue;
      if (t[0] == "end_header") {
        if (!have_format) fail(where + "end_header before any format line");
        header_.data_offset = pos;
        header_.lines = line;
        return;
      }
      if (t[0] == "format") {
        if (have_format) fail(where + "a second format line");
        if (t.size() != 3) fail(where + "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
        if (t[1] == "ascii") header_.format = PlyFormat::ascii;
        else if (t[1] == "binary_little_endian") header_.format = PlyFormat::binary_little_endian;
        else if (t[1] == "binary_big_endian") header_.format = PlyFormat::binary_big_endian;
        else fail(where + "unknown format '" + std::string(t[1]) + "'");
        if (t[2] != "1.0") fail(where + "unsupported version '" + std::string(t[2]) + "' (only 1.0)");
        have_format = true;
        continue;
      }
      if (t[0] == "element") {
        if (t.size() != 3) fail(where + "expected 'element NAME COUNT'");
        Element e;
        e.name = std::string(t[1]);
        e.line = line;
        const auto [ptr, ec] = std::from_chars(t[2].data(), t[2].data() + t[2].size(), e.count);
        if (ec != std::errc() || ptr != t[2].data() + t[2].size()) {
          fail(where + "element '" + e.name + "' count '" + std::string(t[2]) + "' is not a non-negative integer");
        }
        if (find(e.name)) fail(where + "a second element named '" + e.name + "'");
        header_.elements.push_back(std::move(e));
        continue;
      }
      if (t[0] == "property") {
        if (header_.elements.empty()) fail(where + "a property before any element");
        Property p;
        if (t.size() == 5 && t[1] == "list") {
          p.is_list = true;
          const auto count_type = parse_type(t[2]), item_type = parse_type(t[3]);
          if (!count_type || !item_type) fail(where + "unknown type in '" + std::string(text) + "'");
          if (!is_integer(*count_type)) fail(where + "a list count of type '" + std::string(t[2]) + "' (not an integer)");
          p.count_type = *count_type;
          p.type = *item_type;
          p.name = std::string(t[4]);
        } else if (t.size() == 3) {
          const auto type = parse_type(t[1]);
          if (!type) fail(where + "unknown type '" + std::string(t[1]) + "'");
          p.type = *type;
          p.name = std::string(t[2]);
        } else {
          fail(where + "expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'");
        }
        header_.elements.back().properties.push_back(std::move(p));
        continue;
      }
      fail(where + "unknown header keyword '" + std::string(t[0]) + "'");
    }
  }

  // ---- Values -------------------------------------------------------------------------------------------------

  /// The next non-blank data line (ASCII), or nothing at the end of the file.
  std::optional<std::string_view> next_data_line() {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      const std::string_view text = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      if (text.find_first_not_of(" \t\r") != std::string_view::npos) return text;
    }
    return std::nullopt;
  }

  /// Names the value being read in messages: property `prop` of the current element instance; item < 0 is the
  /// property's value (-1) or a list's count (-2), else the list item of that number.
  std::string what(std::size_t prop, std::int64_t item) const {
    std::string s = element_->name + " " + std::to_string(index_) + " property '" + element_->properties[prop].name + "'";
    if (item == -2) return s + " count";
    if (item >= 0) return s + " item " + std::to_string(item);
    return s;
  }

  /// One value of `type` from the current ASCII line's tokens (see what() for prop and item).
  double ascii_value(PlyType type, std::size_t prop, std::int64_t item) {
    if (token_ >= tokens_.size()) fail(at_line() + "the line ends before " + what(prop, item));
    const std::string_view tok = tokens_[token_++];
    const char* first = tok.data();
    const char* last = tok.data() + tok.size();
    double value = 0.0;
    std::from_chars_result r{};
    if (is_integer(type)) {
      long long v = 0;
      r = std::from_chars(first, last, v);
      value = double(v);
    } else if (type == PlyType::float32) {
      float v = 0.0f;
      r = std::from_chars(first, last, v);
      value = v;
    } else {
      r = std::from_chars(first, last, value);
    }
    if (r.ec == std::errc::result_out_of_range || (r.ec == std::errc() && r.ptr == last && is_integer(type))) {
      double lo = 0.0, hi = 0.0;
      if (is_integer(type)) integer_range(type, lo, hi);
      if (r.ec == std::errc::result_out_of_range || value < lo || value > hi) {
        fail(at_line() + what(prop, item) + " '" + std::string(tok) + "' does not fit type " + type_name(type));
      }
    }
    if (r.ec != std::errc() || r.ptr != last) {
      fail(at_line() + what(prop, item) + " '" + std::string(tok) + "' is not a number of type " + type_name(type));
    }
    return value;
  }

  /// One value of `type` from the binary data.
  double binary_value(PlyType type, std::size_t prop, std::int64_t item) {
    const std::size_t size = type_size(type);
    if (bytes_.size() - pos_ < size) fail(binary_place() + "the file ends before " + what(prop, item));
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, size);
    pos_ += size;
    const bool swap = (header_.format == PlyFormat::binary_big_endian) != (std::endian::native == std::endian::big);
    if (swap) std::reverse(b, b + size);
    switch (type) {
      case PlyType::int8: return double(std::int8_t(b[0]));
      case PlyType::uint8: return double(b[0]);
      case PlyType::int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::uint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::uint32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::float32: { float v; std::memcpy(&v, b, 4); return v; }
      case PlyType::float64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0.0;
  }

  std::string binary_place() const {
    return element_->name + " " + std::to_string(index_) + " (byte " + std::to_string(pos_) + "): ";
  }

  double value(PlyType type, std::size_t prop, std::int64_t item) {
    return header_.format == PlyFormat::ascii ? ascii_value(type, prop, item) : binary_value(type, prop, item);
  }

  std::string place() const { return header_.format == PlyFormat::ascii ? at_line() : binary_place(); }

  // ---- Elements -----------------------------------------------------------------------------------------------

  /// The fewest bytes one instance of `e` takes: binary, its scalar sizes and list counts; ASCII, two characters
  /// (a digit and a separator) per scalar or list count.
  std::size_t min_instance_bytes(const Element& e) const {
    std::size_t bytes = 0;
    for (const Property& p : e.properties) {
      bytes += header_.format == PlyFormat::ascii ? 2 : type_size(p.is_list ? p.count_type : p.type);
    }
    return bytes;
  }

  void read_element(const Element& e) {
    element_ = &e;
    if (e.count == 0) return;
    if (e.properties.empty()) fail(header_line(e) + "element '" + e.name + "' has no properties but a count of " + std::to_string(e.count));
    const std::size_t left = bytes_.size() - std::min(pos_, bytes_.size());
    if (e.count > left / min_instance_bytes(e)) {
      fail(header_line(e) + "element '" + e.name + "' count " + std::to_string(e.count) + " needs at least " +
           std::to_string(min_instance_bytes(e)) + " bytes each, but only " + std::to_string(left) +
           " bytes of data are left");
    }
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int xyz[3] = {-1, -1, -1};
    int indices = -1;
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const Property& p = e.properties[i];
      if (is_vertex) {
        for (int a = 0; a < 3; ++a) {
          if (p.name == std::string(1, char('x' + a))) {
            if (p.is_list) fail(header_line(e) + "vertex property '" + p.name + "' is a list");
            xyz[a] = int(i);
          }
        }
      }
      if (is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (!p.is_list) fail(header_line(e) + "face property '" + p.name + "' is not a list");
        if (!is_integer(p.type)) fail(header_line(e) + "face indices of type " + type_name(p.type) + " (not an integer)");
        indices = int(i);
      }
    }
    if (is_vertex && (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)) fail(header_line(e) + "vertex element lacks x, y or z");
    if (is_face && indices < 0) fail(header_line(e) + "face element has no vertex_indices list");
    try {
      if (is_vertex) mesh_.vertices.reserve(std::size_t(e.count));
      if (is_face) mesh_.triangles.reserve(std::size_t(e.count));
    } catch (const std::bad_alloc&) {
      fail(header_line(e) + "out of memory for " + std::to_string(e.count) + " " + e.name + " elements");
    }
    std::vector<std::uint32_t> polygon;
    for (index_ = 0; index_ < e.count; ++index_) {
      if (header_.format == PlyFormat::ascii) {
        const std::optional<std::string_view> text = next_data_line();
        if (!text) {
          fail("line " + std::to_string(line_) + ": the file ends after " + std::to_string(index_) + " of the " +
               std::to_string(e.count) + " " + e.name + " elements");
        }
        tokens_ = tokens_of(*text);
        token_ = 0;
      }
      Vertex p;
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const Property& prop = e.properties[i];
        if (!prop.is_list) {
          const double v = value(prop.type, i, -1);
          for (int a = 0; a < 3; ++a) {
            if (int(i) == xyz[a]) p[a] = static_cast<Coordinate>(v);
          }
          continue;
        }
        const double count = value(prop.count_type, i, -2);
        if (count < 0) fail(place() + what(i, -2) + " " + std::to_string(std::int64_t(count)) + " is negative");
        const bool keep = int(i) == indices;
        if (keep) polygon.clear();
        for (double k = 0; k < count; ++k) {
          const double item = value(prop.type, i, std::int64_t(k));
          if (!keep) continue;
          if (item < 0 || item >= double(vertex_count_)) {
            fail(place() + "face " + std::to_string(index_) + " uses vertex index " + std::to_string(std::int64_t(item)) +
                 ", out of range (the file has " + std::to_string(vertex_count_) + " vertices)");
          }
          polygon.push_back(std::uint32_t(item));
        }
        if (keep) add_polygon(polygon);
      }
      if (is_vertex) mesh_.vertices.push_back(p);
      if (header_.format == PlyFormat::ascii && token_ < tokens_.size()) {
        fail(at_line() + e.name + " " + std::to_string(index_) + " has " + std::to_string(tokens_.size() - token_) +
             " more values than its properties declare ('" + std::string(tokens_[token_]) + "' ...)");
      }
    }
  }

  /// Fan-triangulates a polygon (0, i, i+1); fewer than three indices add nothing.
  void add_polygon(const std::vector<std::uint32_t>& polygon) {
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      if (mesh_.triangles.size() >= std::numeric_limits<std::uint32_t>::max() - 1) {
        fail(place() + "more than 2^32 - 2 triangles");
      }
      mesh_.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    }
  }

  using Vertex = typename decltype(Mesh::vertices)::value_type;
  using Coordinate = std::remove_cvref_t<decltype(std::declval<Vertex&>()[0])>;

  std::span<const std::byte> bytes_;
  std::string_view text_;
  std::string name_;
  Header header_;
  Mesh mesh_;
  std::uint64_t vertex_count_ = 0;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
  const Element* element_ = nullptr;
  std::uint64_t index_ = 0;
  std::vector<std::string_view> tokens_;
  std::size_t token_ = 0;
};

/// The whole of a regular file, for parse_ply().
std::vector<std::byte> read_ply_bytes(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error("cannot read PLY file '" + path.string() + "': not a regular file (or it does not exist)");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw Error("cannot read PLY file '" + path.string() + "': " + ec.message());
  std::vector<std::byte> bytes;
  try {
    bytes.resize(static_cast<std::size_t>(size));
  } catch (const std::bad_alloc&) {
    throw Error("cannot read PLY file '" + path.string() + "': out of memory for its " + std::to_string(size) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in || (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))) {
    throw Error("cannot read PLY file '" + path.string() + "': read error");
  }
  return bytes;
}

}  // namespace

bool looks_like_ply(std::span<const std::byte> bytes) {
  const std::string_view t = as_text(bytes);
  if (t.size() < 3) return false;
  for (std::size_t i = 0; i < 3; ++i) {
    if (std::tolower(static_cast<unsigned char>(t[i])) != "ply"[i]) return false;
  }
  return t.size() == 3 || std::isspace(static_cast<unsigned char>(t[3]));
}

bool reads_as_ply(const std::filesystem::path& path, std::span<const std::byte> first_bytes) {
  return looks_like_ply(first_bytes) || lowercase_extension(path) == ".ply";
}

TriangleMesh parse_ply(std::span<const std::byte> bytes, const std::string& name) {
  return PlyParser<TriangleMesh>(bytes, name).parse();
}

TriangleMeshD parse_ply_double(std::span<const std::byte> bytes, const std::string& name) {
  return PlyParser<TriangleMeshD>(bytes, name).parse();
}

TriangleMesh read_ply(const std::filesystem::path& path) { return parse_ply(read_ply_bytes(path), path.string()); }

TriangleMeshD read_ply_double(const std::filesystem::path& path) {
  return parse_ply_double(read_ply_bytes(path), path.string());
}

}  // namespace rayaccel

