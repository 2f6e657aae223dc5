// Output files written whole or not at all: bytes go to a temporary file beside the target, every write is checked,
// and the temporary replaces the target by rename() only once complete, so a failed write (full disk, lost
// directory) leaves the previous file intact and is reported. Plus the check of an output path before any work.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace rayaccel {

/// Throws an Error naming `what` and `path` unless a file can be written there: the path is not empty and not a
/// directory, and its directory exists and is writable (an existing non-regular file such as /dev/null or
/// /dev/stdout is accepted as is).
void check_output_path(const std::filesystem::path& path, std::string_view what);

/// Throws an Error naming `what` and `path` unless `path` is a writable directory or can be created as one.
void check_output_directory(const std::filesystem::path& path, std::string_view what);

/// Writes `bytes` to `path`: into a temporary file in the same directory, checked write by write and flushed to
/// disk, then renamed over `path`. On failure the temporary is removed, `path` is untouched and an Error names
/// `what`, the path and the cause. An existing non-regular target (a device, a pipe) is written in place, each write
/// checked (writing to /dev/full fails with "No space left on device").
void write_file_atomically(const std::filesystem::path& path, std::span<const std::byte> bytes, std::string_view what);

/// The same for text.
void write_file_atomically(const std::filesystem::path& path, std::string_view text, std::string_view what);

}  // namespace rayaccel
