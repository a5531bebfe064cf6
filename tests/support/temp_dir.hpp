// temp_dir.hpp: a fresh temporary directory per test case, removed (with its contents) at the end.
// Header-only test support; included by tests/test_*.cpp as "support/temp_dir.hpp".
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace bemsurg_test {

/// A new, empty directory `<temp>/<prefix><pid>_<n>`, unique within and across test processes
/// (the pid separates processes, an atomic counter the cases of one process), removed on destruction.
struct TempDir {
  std::filesystem::path path;

  explicit TempDir(const std::string& prefix) {
    static std::atomic<int> counter{0};
    path = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path);  // a leftover from a crashed run with a recycled pid
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// The path of `name` inside the directory (the file need not exist).
  std::string file(const std::string& name) const { return (path / name).string(); }

  /// Writes `text` to `name` inside the directory and returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return file(name);
  }
};

}  // namespace bemsurg_test
