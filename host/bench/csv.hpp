#pragma once
// Benchmark records as CSV, one row per record, for spreadsheets and plotting tools. Columns: the
// fixed fields of the record format (bench/record.hpp) in its order, then every extra field any
// record has, in first-seen order. Cells are RFC 4180 (quoted when they hold a comma, quote or line
// break). Extra values: strings as they are, numbers and booleans as JSON, objects and arrays as
// JSON text; an empty cell is a field the record lacks. The machine description is not part of
// the CSV (it is in the JSON file).
#include <string>

#include "bench/record.hpp"

namespace splatcl::bench {

std::string to_csv(const Results& results);
// Inverse of to_csv (machine left empty). A cell of an extra column that parses as a JSON number,
// boolean, object or array becomes that value, else a string. Throws Error naming the line.
Results results_from_csv(const std::string& text);

// Written through a temporary file renamed when complete.
void write_csv(const std::string& path, const Results& results);
// Throws Error naming the file.
Results read_csv(const std::string& path);

}  // namespace splatcl::bench
