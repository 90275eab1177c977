// Tables as OpenEXR files (docs/lut-format.md): channels "value" and "error", the axes flattened
// into a 2-D image (width = count of the last, fastest axis; height = product of the others),
// metadata in string attributes "ganzfeld.*".
#pragma once

#include <string>

#include "tables/table.h"

namespace ganzfeld::tables {

/// Writes the table to a temporary file beside `path` and renames it over `path`: readers never
/// see a partial table, and on any failure (InputError) nothing is left at `path` or beside it.
void write_table(const Table& table, const std::string& path);

/// Reads and validates a table; anything that is not a complete, consistent law table (format
/// versions 1, 2, 4, 5) is refused with a one-line InputError naming the file.
Table read_table(const std::string& path);

/// A warped table's ganzfeld.warp attribute, JSON text: {"mix", "envelope", "samples": [[shift, along,
/// across], ...]}.
std::string warp_text(const Warp& warp);

}  // namespace ganzfeld::tables
