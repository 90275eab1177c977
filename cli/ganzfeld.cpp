// The ganzfeld command (cli/run.h holds the whole of it, so that the fuzzer can call it).
#include <csignal>

#include "cli/run.h"

int main(int argc, char** argv) {
  // Past a file-size limit (ulimit -f) the kernel's default is to kill the process with SIGXFSZ,
  // leaving a temporary file behind; ignored, the write fails with EFBIG instead and the atomic
  // writer removes the temporary file and reports one line (exit 2).
  std::signal(SIGXFSZ, SIG_IGN);
  return ganzfeld::cli::run_cli(argc, argv);
}
