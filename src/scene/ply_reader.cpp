// The PLY reader (ply_reader.h): after the header (ply_header.h), the data read element by element, ASCII or binary
// of either byte order, each count checked against the bytes left; coordinates kept in the mesh's own precision.
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
#include "ply_header.h"

namespace rayaccel {

namespace {

using ply::Element;
using ply::Header;
using ply::PlyFormat;
using ply::PlyType;
using ply::Property;
using ply::is_integer;
using ply::integer_range;
using ply::tokens_of;
using ply::type_name;
using ply::type_size;

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
    header_ = ply::parse_header(text_, name_);
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

