// The ganzfeld command (cli/run.h holds the whole of it, so that the fuzzer can call it).
#include "cli/run.h"

int main(int argc, char** argv) { return ganzfeld::cli::run_cli(argc, argv); }
