// What every fuzz target shares: the contract a reader must keep on any bytes (return, or throw
// a one-line InputError; anything else is a finding), and a per-process scratch file for the
// readers that take a path.
#pragma once

#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "util/error.h"

namespace ganzfeld::fuzz {

inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs `read`; an InputError must be one line (util/error.h), any other exception escapes
/// and libFuzzer reports it (uncaught exception = crash), as ASan/UBSan report memory and UB.
template <class F>
void expect_clean(F&& read) {
  try {
    read();
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.empty() || what.find('\n') != std::string::npos) {
      std::fprintf(stderr, "InputError is not one line: [%s]\n", what.c_str());
      std::abort();
    }
  }
}

/// A scratch file of this process (libFuzzer -jobs/-fork run several), holding `bytes`.
inline std::string scratch_file(const std::uint8_t* data, std::size_t size, const char* extension) {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("ganzfeld-fuzz-" + std::to_string(::getpid()) + extension)).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace ganzfeld::fuzz
