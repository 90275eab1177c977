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

/// Reads and validates a table; anything that is not a complete, consistent format-version-1
/// table is refused with a one-line InputError naming the file.
Table read_table(const std::string& path);

}  // namespace ganzfeld::tables
