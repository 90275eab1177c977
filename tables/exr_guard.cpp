#include "tables/exr_guard.h"

#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "util/error.h"

namespace ganzfeld::tables {

namespace {

// OpenEXR file layout ("OpenEXR File Layout", openexr.com): version field flags and the scanlines
// per chunk of each compression (index = the compression attribute's value).
constexpr std::uint32_t kTiledFlag = 0x200, kLongNamesFlag = 0x400, kDeepFlag = 0x800, kMultiPartFlag = 0x1000;
constexpr std::array<int, 10> kLinesPerChunk{1, 1, 1, 16, 32, 16, 32, 32, 32, 256};  // NO .. DWAB

/// A name from the file, printable and on one line for a message.
std::string printable(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return text;
}

class HeaderWalk {
 public:
  HeaderWalk(const std::string& path, std::uint64_t size) : path_(path), size_(size), in_(path, std::ios::binary) {
    if (!in_) refuse("cannot be read");
  }

  [[noreturn]] void refuse(const std::string& why) const { throw InputError("table '" + path_ + "': " + why); }

  std::uint64_t position() const { return pos_; }

  std::string bytes(std::uint64_t n, const std::string& what) {
    if (n > size_ - pos_)
      refuse(what + " declares " + std::to_string(n) + " bytes but only " + std::to_string(size_ - pos_) +
             " remain in the file (truncated or forged)");
    std::string out(static_cast<std::size_t>(n), '\0');
    in_.read(out.data(), static_cast<std::streamsize>(n));
    if (!in_) refuse("cannot be read (truncated file)");
    pos_ += n;
    return out;
  }

  void skip(std::uint64_t n, const std::string& what) {
    if (n > size_ - pos_)
      refuse(what + " declares " + std::to_string(n) + " bytes but only " + std::to_string(size_ - pos_) +
             " remain in the file (truncated or forged)");
    in_.seekg(static_cast<std::streamoff>(n), std::ios::cur);
    pos_ += n;
  }

  /// A null-terminated name of at most `max` characters ("" = the end of the header).
  std::string name(std::size_t max, const char* what) {
    std::string out;
    for (;;) {
      if (pos_ >= size_) refuse(std::string("truncated file (inside the header's ") + what + ")");
      const int c = in_.get();
      if (c == std::char_traits<char>::eof()) refuse("cannot be read (truncated file)");
      ++pos_;
      if (c == 0) return out;
      if (out.size() == max)
        refuse(std::string("header ") + what + " longer than " + std::to_string(max) + " characters");
      out.push_back(static_cast<char>(c));
    }
  }

  static std::int32_t i32(const std::string& b, std::size_t at) {
    const auto u = [&](std::size_t k) { return static_cast<std::uint32_t>(static_cast<unsigned char>(b[at + k])); };
    return static_cast<std::int32_t>(u(0) | u(1) << 8 | u(2) << 16 | u(3) << 24);
  }

 private:
  std::string path_;
  std::uint64_t size_, pos_ = 0;
  std::ifstream in_;
};

/// Bytes per pixel of all channels of a chlist value (name\0, int32 type, 4 bytes, 2 × int32,
/// then an empty name). OpenEXR reads up to the empty name whatever the declared size says, so
/// the list must end exactly at the value's last byte, or its walk and ours would part.
std::uint64_t bytes_per_pixel(const std::string& v, const HeaderWalk& walk) {
  std::uint64_t bytes = 0;
  std::size_t at = 0;
  while (at < v.size() && v[at] != '\0') {
    const auto end = v.find('\0', at);
    if (end == std::string::npos || end + 17 > v.size()) walk.refuse("attribute 'channels' is malformed");
    const std::int32_t type = HeaderWalk::i32(v, end + 1);
    if (type < 0 || type > 2)
      walk.refuse("channel '" + printable(v.substr(at, end - at)) + "' has pixel type " + std::to_string(type) +
                  "; allowed: 0, 1, 2");
    bytes += type == 1 ? 2 : 4;
    at = end + 17;
  }
  if (at + 1 != v.size()) walk.refuse("attribute 'channels' does not end where its declared size says");
  return bytes;
}

/// Value sizes of the attribute types OpenEXR 3.1 reads with a fixed size whatever the declared
/// size says (ImfHeader.cpp registers them); a declared size that differs would make OpenEXR's walk
/// and ours part. string, floatvector and unknown (opaque) types are read with the declared size.
std::optional<std::int32_t> fixed_size(const std::string& type) {
  static const std::map<std::string, std::int32_t> sizes{{"box2i", 16},
                                                         {"box2f", 16},
                                                         {"chromaticities", 32},
                                                         {"compression", 1},
                                                         {"deepImageState", 1},
                                                         {"double", 8},
                                                         {"envmap", 1},
                                                         {"float", 4},
                                                         {"int", 4},
                                                         {"keycode", 28},
                                                         {"lineOrder", 1},
                                                         {"m33f", 36},
                                                         {"m33d", 72},
                                                         {"m44f", 64},
                                                         {"m44d", 128},
                                                         {"rational", 8},
                                                         {"tiledesc", 9},
                                                         {"timecode", 8},
                                                         {"v2i", 8},
                                                         {"v2f", 8},
                                                         {"v2d", 16},
                                                         {"v3i", 12},
                                                         {"v3f", 12},
                                                         {"v3d", 24}};
  const auto it = sizes.find(type);
  return it == sizes.end() ? std::nullopt : std::optional<std::int32_t>(it->second);
}

}  // namespace

void check_exr_sizes(const std::string& path) {
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError("table '" + path + "': cannot be read");
  HeaderWalk walk(path, size);
  const std::string magic = walk.bytes(8, "the OpenEXR magic number and version");
  const auto version = static_cast<std::uint32_t>(HeaderWalk::i32(magic, 4));
  if (version & (kTiledFlag | kDeepFlag | kMultiPartFlag))
    walk.refuse("is a tiled, deep or multi-part OpenEXR file; ganzfeld tables are single-part scanline images");
  const std::size_t max_name = (version & kLongNamesFlag) ? 255 : 31;

  bool have_window = false;
  std::int64_t width = 0, height = 0;
  int compression = 0;
  std::uint64_t pixel_bytes = 0;
  for (;;) {
    const std::string name = walk.name(max_name, "attribute name");
    if (name.empty()) break;
    const std::string type = walk.name(max_name, "attribute type");
    const std::string what = "attribute '" + printable(name) + "'";
    const std::int32_t declared = HeaderWalk::i32(walk.bytes(4, what), 0);
    if (declared < 0) walk.refuse(what + " declares a negative size " + std::to_string(declared));
    // Types whose values hold sizes of their own that OpenEXR allocates (a preview's width × height,
    // a string vector's lengths, an ID manifest's uncompressed size): no ganzfeld table has them.
    if (type == "preview" || type == "stringvector" || type == "idmanifest")
      walk.refuse(what + " is of type '" + type + "', which ganzfeld tables do not use");
    if (const auto size = fixed_size(type); size && declared != *size)
      walk.refuse(what + " of type '" + type + "' declares " + std::to_string(declared) + " bytes; it has " +
                  std::to_string(*size));
    if (name == "dataWindow" && type == "box2i" && declared == 16) {
      const std::string v = walk.bytes(16, what);
      width = std::int64_t{HeaderWalk::i32(v, 8)} - HeaderWalk::i32(v, 0) + 1;
      height = std::int64_t{HeaderWalk::i32(v, 12)} - HeaderWalk::i32(v, 4) + 1;
      have_window = true;
    } else if (name == "compression" && type == "compression" && declared == 1) {
      compression = static_cast<unsigned char>(walk.bytes(1, what)[0]);
      if (compression >= static_cast<int>(kLinesPerChunk.size()))
        walk.refuse("attribute 'compression' is " + std::to_string(compression) + "; allowed: 0 to 9");
    } else if (type == "chlist") {  // OpenEXR reads any chlist up to its terminator
      const std::uint64_t bytes = bytes_per_pixel(walk.bytes(static_cast<std::uint64_t>(declared), what), walk);
      if (name == "channels") pixel_bytes = bytes;
    } else {
      walk.skip(static_cast<std::uint64_t>(declared), what);
    }
  }
  if (!have_window) return;  // OpenEXR refuses a header without a data window itself
  if (width <= 0 || height <= 0)
    walk.refuse("data window is " + std::to_string(width) + "x" + std::to_string(height) + " pixels");
  const std::uint64_t lines = static_cast<std::uint64_t>(kLinesPerChunk[static_cast<std::size_t>(compression)]);
  const std::uint64_t chunks = (static_cast<std::uint64_t>(height) + lines - 1) / lines;
  // Each chunk: an 8-byte entry in the offset table, then at least its int32 y and int32 size.
  if (chunks > (size - walk.position()) / 16)
    walk.refuse("data window of " + std::to_string(height) + " scanlines needs " + std::to_string(chunks) +
                " chunks, more than the " + std::to_string(size) + "-byte file holds (truncated or forged)");
  // OpenEXR buffers whole chunks; width · rows may overflow 64 bits, so divide the budget instead.
  const std::uint64_t rows = chunks * lines;
  const std::uint64_t budget = size * kMaxExpansion / (pixel_bytes == 0 ? 1 : pixel_bytes);
  if (static_cast<std::uint64_t>(width) > budget / rows)
    walk.refuse("data window of " + std::to_string(width) + "x" + std::to_string(height) + " pixels (" +
                std::to_string(pixel_bytes) + " bytes each) is more than " + std::to_string(kMaxExpansion) +
                " times the " + std::to_string(size) + "-byte file (truncated or forged)");
}

}  // namespace ganzfeld::tables
