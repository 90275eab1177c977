// Sizes an OpenEXR file declares, checked against the file's length before OpenEXR reads it.
//
// OpenEXR 3.1 trusts the sizes it reads: Header::readFrom allocates each attribute's declared
// size (an 852-byte file declaring a 1.6 GB attribute makes OpaqueAttribute::readValueFrom
// allocate 1.6 GB), and InputFile allocates its line-offset table and line buffers from the
// declared data window. This guard walks the header itself (OpenEXR file layout: magic, version,
// then attributes "name\0 type\0 int32 size value" up to an empty name) and refuses, before
// OpenEXR sees the file, anything whose declared sizes a file of its length cannot hold:
//  - an attribute larger than the bytes left in the file;
//  - a tiled, deep or multi-part file (ganzfeld tables are single-part scanline images);
//  - a data window whose line-offset table and chunk headers (8 + 8 bytes per chunk) do not fit;
//  - pixels (width × height × bytes per pixel of all channels) more than kMaxExpansion times
//    the file's length: deflate cannot compress better than 1032:1 (zlib technical details,
//    "maximum compression factor"), and OpenEXR's other codecs are below that on real tables.
// So a table of N bytes makes the reader allocate at most ~kMaxExpansion·N bytes of pixels and
// ~N bytes of header, whatever it declares.
#pragma once

#include <cstdint>
#include <string>

namespace ganzfeld::tables {

/// Pixel bytes a file may declare per byte of file (deflate's maximum compression ratio + slack).
inline constexpr std::uint64_t kMaxExpansion = 1100;

/// Throws InputError("table 'PATH': ...", one line, naming the bad attribute or size) when the
/// file's declared sizes do not fit its length (see above). Does not judge anything else.
void check_exr_sizes(const std::string& path);

}  // namespace ganzfeld::tables
