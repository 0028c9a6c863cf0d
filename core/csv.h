#pragma once
// CSV files of the dataset contract: '#' lines are headers/comments, blank lines are ignored,
// fields are separated by commas. Numbers are written so they read back exactly enough for the
// contract (9 significant digits) and NaN is written as `nan`.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pensight {

// What a table does with a row whose field count is out of range: throw (files pensight writes
// or that define the run), or set it aside in rejected() (sensor logs, where a logger glitch must
// not lose a dive).
enum class BadRows { kThrow, kSetAside };

class CsvTable {
 public:
  // A row of `file` that the table set aside: its line and what was wrong with it.
  struct Rejected {
    int line = 0;
    std::string message;
  };

  // Reads `file`; every row must have between min_fields and max_fields fields.
  CsvTable(const std::filesystem::path& file, size_t min_fields, size_t max_fields,
           BadRows bad_rows = BadRows::kThrow);

  // The column names of the first '#' line (its '#' dropped), for files read by column name.
  const std::vector<std::string>& header() const { return header_; }
  size_t rows() const { return rows_.size(); }
  size_t fields(size_t row) const { return rows_[row].fields.size(); }
  const std::string& text(size_t row, size_t field) const { return rows_[row].fields[field]; }
  int line(size_t row) const { return rows_[row].line; }  // 1-based line in the file
  const std::string& file() const { return file_; }
  // Rows with a field count out of range (BadRows::kSetAside only), in file order.
  const std::vector<Rejected>& rejected() const { return rejected_; }
  // Parse a field; `nan` is accepted for numbers. Errors name the file, line and column.
  double number(size_t row, size_t field) const;
  int64_t integer(size_t row, size_t field) const;

 private:
  struct Row {
    int line = 0;
    std::vector<std::string> fields;
  };
  [[noreturn]] void fail(size_t row, size_t field, const std::string& message) const;

  std::string file_;
  std::vector<std::string> header_;
  std::vector<Row> rows_;
  std::vector<Rejected> rejected_;
};

// "nan" for NaN, otherwise the shortest of %.9g.
std::string format_number(double v);

}  // namespace pensight
