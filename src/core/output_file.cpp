// Whole-or-nothing output files (see output_file.h) and batches of them (output_batch.h): POSIX
// open/write/fsync/rename, each call checked.
#include "rayaccel/core/output_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <random>

#include "rayaccel/core/error.h"
#include "rayaccel/core/output_batch.h"

namespace rayaccel {

namespace {

std::string describe(std::string_view what, const std::filesystem::path& path) {
  return "cannot write " + std::string(what) + " '" + path.string() + "'";
}

/// The directory a file at `path` goes into ("." for a bare name).
std::filesystem::path parent_of(const std::filesystem::path& path) {
  const std::filesystem::path parent = path.parent_path();
  return parent.empty() ? std::filesystem::path(".") : parent;
}

/// Writes all of `bytes` to `fd`, retrying short writes and EINTR; false with errno set on failure.
bool write_all(int fd, const std::byte* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (n == 0) {
      errno = EIO;
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

/// A name for the temporary beside `path` that no other writer picks: the target's name, the process id and a
/// random suffix, hidden.
std::filesystem::path temporary_beside(const std::filesystem::path& path) {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  std::string name(".");  // appended piece by piece (GCC 12 warns, wrongly, about "." + string&&)
  name += path.filename().string();
  name += ".tmp";
  name += std::to_string(::getpid());
  name += "-";
  name += std::to_string(rng() % 1000000000u);
  return parent_of(path) / name;
}

}  // namespace

void check_output_path(const std::filesystem::path& path, std::string_view what) {
  if (path.empty()) throw Error(describe(what, path) + ": the path is empty");
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(status)) throw Error(describe(what, path) + ": it is a directory");
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    if (::access(path.c_str(), W_OK) != 0) throw Error(describe(what, path) + ": " + std::strerror(errno));
    return;  // a device or pipe, written in place
  }
  const std::filesystem::path dir = parent_of(path);
  if (!std::filesystem::is_directory(dir, ec)) {
    throw Error(describe(what, path) + ": directory '" + dir.string() + "' does not exist");
  }
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    throw Error(describe(what, path) + ": directory '" + dir.string() + "' is not writable (" + std::strerror(errno) +
                ")");
  }
}

void check_output_directory(const std::filesystem::path& path, std::string_view what) {
  if (path.empty()) throw Error("cannot write " + std::string(what) + " into '': the path is empty");
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    if (!std::filesystem::is_directory(path, ec)) {
      throw Error("cannot write " + std::string(what) + " into '" + path.string() + "': not a directory");
    }
    if (::access(path.c_str(), W_OK | X_OK) != 0) {
      throw Error("cannot write " + std::string(what) + " into '" + path.string() + "': " + std::strerror(errno));
    }
    return;
  }
  // Created now (empty if the work fails later), so that a path that cannot be created is reported before the work.
  std::filesystem::create_directories(path, ec);
  if (ec) throw Error("cannot create directory '" + path.string() + "' for " + std::string(what) + ": " + ec.message());
}

void write_file_atomically(const std::filesystem::path& path, std::span<const std::byte> bytes,
                           std::string_view what) {
  check_output_path(path, what);
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec)) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) throw Error(describe(what, path) + ": " + std::strerror(errno));
    const bool written = write_all(fd, bytes.data(), bytes.size());
    const int saved = errno;
    if (::close(fd) != 0 && written) throw Error(describe(what, path) + ": " + std::strerror(errno));
    if (!written) throw Error(describe(what, path) + ": " + std::strerror(saved));
    return;
  }
  const std::filesystem::path temp = temporary_beside(path);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) throw Error(describe(what, path) + ": cannot create '" + temp.string() + "': " + std::strerror(errno));
  const auto fail = [&](const std::string& cause) {
    ::close(fd);
    ::unlink(temp.c_str());
    throw Error(describe(what, path) + ": " + cause + " (the previous file, if any, is unchanged)");
  };
  if (!write_all(fd, bytes.data(), bytes.size())) fail(std::strerror(errno));
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) fail(std::strerror(errno));
  if (::close(fd) != 0) {
    const int saved = errno;
    ::unlink(temp.c_str());
    throw Error(describe(what, path) + ": " + std::strerror(saved) + " (the previous file, if any, is unchanged)");
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int saved = errno;
    ::unlink(temp.c_str());
    throw Error(describe(what, path) + ": rename failed: " + std::strerror(saved));
  }
}

OutputBatch::~OutputBatch() {
  for (const auto& [temp, target] : staged_) {
    if (temp != target) ::unlink(temp.c_str());
  }
}

std::filesystem::path OutputBatch::stage(const std::filesystem::path& target) {
  std::error_code ec;
  const bool in_place = std::filesystem::exists(target, ec) && !std::filesystem::is_regular_file(target, ec);
  staged_.emplace_back(in_place ? target : temporary_beside(target), target);
  return staged_.back().first;
}

void OutputBatch::commit() {
  for (const auto& [temp, target] : staged_) {
    if (temp == target) continue;
    if (::rename(temp.c_str(), target.c_str()) != 0) {
      throw Error("cannot write '" + target.string() + "': rename of '" + temp.string() + "' failed: " +
                  std::strerror(errno));
    }
  }
  staged_.clear();
}

void write_file_atomically(const std::filesystem::path& path, std::string_view text, std::string_view what) {
  write_file_atomically(path, std::as_bytes(std::span(text.data(), text.size())), what);
}

}  // namespace rayaccel
