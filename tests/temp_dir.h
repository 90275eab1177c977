// A per-process temporary directory for a test binary, removed after the last test.
#pragma once

#include <unistd.h>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace ganzfeld::testing_support {

/// <system temp>/ganzfeld_test-<pid> (one per test process), created on first use.
inline std::string temp_dir() {
  static const std::string dir = [] {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("ganzfeld_test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  return dir;
}

/// Removes the temporary directory after the last test.
class RemoveTempDir : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(temp_dir(), ec);
  }
};
inline const auto* const kRemoveTempDir = ::testing::AddGlobalTestEnvironment(new RemoveTempDir);

}  // namespace ganzfeld::testing_support
