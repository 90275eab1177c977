// The command line (cli/run.h): the input is argv after "ganzfeld", one argument per line. Only
// parsed (run_cli's parse_only): the actions write files or run long. The exit code must be 0 or
// 2; stdout and stderr are silenced by scripts/fuzz (-close_fd_mask=3).
#include <algorithm>
#include <cstdlib>
#include <vector>

#include "cli/run.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = ganzfeld::fuzz::text(data, size);
  std::vector<std::string> args{"ganzfeld"};
  std::size_t start = 0;
  while (start <= input.size() && args.size() < 64) {
    const std::size_t end = std::min(input.find('\n', start), input.size());
    args.push_back(input.substr(start, end - start));
    start = end + 1;
  }
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  const int code = ganzfeld::cli::run_cli(static_cast<int>(argv.size()), argv.data(), /*parse_only=*/true);
  if (code != 0 && code != 2) {  // parse_only: 0 (a sub-command, --help, --version) or 2 (bad input)
    std::fprintf(stderr, "run_cli returned %d\n", code);
    std::abort();
  }
  return 0;
}
