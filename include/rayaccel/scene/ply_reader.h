// The PLY reader (Turk's polygon file format, as the Stanford / Paul Bourke description defines it): ASCII and
// binary little- and big-endian, vertex x/y/z of any numeric type, face index lists of any count and index type,
// every count checked against the file's size before anything is allocated.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

#include "rayaccel/core/primitives.h"

namespace rayaccel {

struct TriangleMeshD;  // core/mesh_d.h

/// True when `bytes` start like a PLY file: "ply" in any case, then whitespace or nothing (so "PLY", "ply " and
/// "ply\r" reach parse_ply(), which refuses what is not exactly "ply", rather than another reader).
bool looks_like_ply(std::span<const std::byte> bytes);

/// True when mesh import reads the file as PLY, with read_ply(): its first bytes look_like_ply(), or it is called
/// *.ply in any case (then read_ply() says what is wrong with it; no other reader sees it).
bool reads_as_ply(const std::filesystem::path& path, std::span<const std::byte> first_bytes);

/// Parses a PLY file held in memory; `name` stands for it in messages. Vertices are the `vertex` element's x, y, z
/// (rounded to float); triangles come from the `face` element's `vertex_indices` (or `vertex_index`) lists in file
/// order, each polygon fan-triangulated as (0, i, i+1); faces of fewer than three indices are skipped. Other
/// elements and properties are read past. Throws Error naming the file, the header or data line (ASCII) or the
/// element and its index (binary), and the value at fault for: a bad header, a count the file is too small to
/// hold, a missing or extra value, a number that does not parse or does not fit its declared type, an index out of
/// range, or a file that ends early.
TriangleMesh parse_ply(std::span<const std::byte> bytes, const std::string& name);

/// Reads a PLY file (a regular file, read whole) with parse_ply().
TriangleMesh read_ply(const std::filesystem::path& path);

/// parse_ply() for the double path: the same parsing and checks, but vertex coordinates are kept as read (a
/// `double` property keeps all 53 bits; float and integer properties are exact in double). DoubleScene then checks
/// them against the double domain.
TriangleMeshD parse_ply_double(std::span<const std::byte> bytes, const std::string& name);
TriangleMeshD read_ply_double(const std::filesystem::path& path);

}  // namespace rayaccel
