#include "util/atomic_file.h"

#include <unistd.h>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "util/error.h"

namespace ganzfeld {

namespace fs = std::filesystem;

namespace {
std::string temp_path_for(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Built with += : g++ 12 warns falsely (-Wrestrict) on "." + std::string&&.
  std::string name(".");
  name += target.filename().string();
  name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return (dir / name).string();
}

std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}
}  // namespace

void write_atomically(const std::string& path, const std::function<void(const std::string& temp)>& write,
                      const std::string& noun) {
  const std::string temp = temp_path_for(fs::path(path));
  auto remove_temp = [&] {
    std::error_code ec;
    fs::remove(temp, ec);
  };
  auto refuse = [&](const std::string& why) {
    remove_temp();
    throw InputError("cannot write " + (noun.empty() ? "" : noun + " ") + "'" + path + "': " + one_line(why));
  };
  try {
    write(temp);
  } catch (const InputError&) {
    remove_temp();
    throw;
  } catch (const std::exception& e) { refuse(e.what()); }
  std::error_code ec;
  fs::rename(temp, path, ec);
  if (ec) refuse(ec.message());
}

void write_text_atomically(const std::string& path, const std::string& content, const std::string& noun) {
  write_atomically(
      path,
      [&](const std::string& temp) {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error("cannot create a file in its directory (missing or not writable)");
        out << content;
        out.close();
        if (!out) throw std::runtime_error("the write failed (disk full?)");
      },
      noun);
}

void check_writable(const std::string& path) {
  const fs::path target(path);
  if (target.filename().empty()) throw InputError("cannot write '" + path + "': expected a file name, not a directory");
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError("cannot write '" + path + "': directory '" + dir.string() + "' does not exist");
  if (fs::is_directory(target, ec)) throw InputError("cannot write '" + path + "': it is a directory");
  if (::access(dir.c_str(), W_OK) != 0)
    throw InputError("cannot write '" + path + "': directory '" + dir.string() + "' is not writable");
}

}  // namespace ganzfeld
