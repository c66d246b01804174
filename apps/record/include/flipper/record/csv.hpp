#pragma once
/// @file csv.hpp
/// Comma-separated values as RFC 4180 writes them: a field with a comma, quote or line break is
/// quoted, quotes doubled. The one CSV dialect of run folders (docs/experiments.md §3).

#include <string>
#include <vector>

namespace flipper::record {

/// One field, quoted when it needs to be.
std::string csv_field(const std::string& text);
/// Fields joined by commas (no line end).
std::string csv_line(const std::vector<std::string>& fields);

/// A whole CSV text: its header and rows. Throws sdk::Error(bad_request) for an unterminated
/// quote or a row whose field count differs from the header's, naming `where` and the line.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  /// The index of column `name`; throws sdk::Error(bad_request) naming `where` when absent.
  std::size_t column(const std::string& name, const std::string& where) const;
};
CsvTable parse_csv(const std::string& text, const std::string& where);
/// Reads and parses a CSV file (errors name the file).
CsvTable read_csv(const std::string& path);

/// A double as the shortest text that reads back as the same value ("0.1", "3830", "1e-05").
std::string exact_number(double value);

}  // namespace flipper::record
