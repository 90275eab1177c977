// The one progress reporter: "\rLABEL [####......]  42% (55050/131072), 3 s left" on stderr,
// redrawn in place, only when stderr is a terminal (logs and pipes get nothing).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace ganzfeld::util {

/// A progress callback (done, total) that draws a bar labelled `label`, or an empty function
/// when `quiet` or stderr is not a terminal. Calls must be serialized, with increasing `done`.
std::function<void(std::uint64_t done, std::uint64_t total)> progress_bar(const std::string& label, bool quiet = false);

}  // namespace ganzfeld::util
