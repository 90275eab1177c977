// Atomic output: every file ganzfeld writes (tables, images, plots, reports) appears whole or
// not at all. util/ is below every module that writes files.
#pragma once

#include <functional>
#include <string>

namespace ganzfeld {

/// Calls `write(temp)` with a temporary path beside `path` (same directory, so the rename is
/// atomic), then renames the temporary file over `path`. If `write` throws or the rename fails,
/// the temporary file is removed: an InputError passes through unchanged, anything else becomes
/// the one-line InputError "cannot write [NOUN ]'PATH': WHY".
void write_atomically(const std::string& path, const std::function<void(const std::string& temp)>& write,
                      const std::string& noun = "");

/// Refuses (InputError) an output path whose directory does not exist or is not writable, or
/// that names a directory: call it before long work so the work is not wasted.
void check_writable(const std::string& path);

/// write_atomically for a whole text.
void write_text_atomically(const std::string& path, const std::string& content, const std::string& noun = "");

}  // namespace ganzfeld
