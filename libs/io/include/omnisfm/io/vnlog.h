#pragma once
// vnlog tables, as mrcal writes and reads them:
//   ## a comment (before the header, only '##' or '#!' lines are comments)
//   # x y z          <- the header: the first other line starting with '#'
//   1.5 - 3          <- whitespace-separated fields; '-' is a missing value (NaN)
//   # a comment
//   4 5 6 # a note   <- a '#' ends a row's fields, as vnlog's own readers take it
// Blank lines are skipped; every data line has exactly one field per column.

#include <cstddef>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace omnisfm::io {

// A table read one row at a time, for files too long to hold: the same format and errors as
// VnlogTable.
class VnlogReader {
 public:
  // Opens the file and reads up to its header; throws InputError naming the file (and line).
  explicit VnlogReader(const std::string& path);
  // Reads from `in`, which must outlive the reader; `display_name` names it in errors.
  VnlogReader(std::istream& in, const std::string& display_name);
  ~VnlogReader();

  const std::string& file() const { return file_; }
  const std::vector<std::string>& column_names() const { return columns_; }
  // The column's index; throws InputError naming the file when there is no such column.
  std::size_t column(const std::string& name) const;
  std::vector<std::size_t> columns(const std::vector<std::string>& names) const;

  // Moves to the next data row; false at the end. Throws InputError for a malformed line.
  bool next();
  const std::string& text(std::size_t column) const { return fields_[column]; }
  const std::vector<std::string>& fields() const { return fields_; }
  // The field as a number (NaN when missing); throws InputError "FILE:LINE: column 'c': ...".
  double number(std::size_t column) const;
  int line() const { return line_; }

 private:
  void read_header();

  std::unique_ptr<std::istream> owned_;
  std::istream* in_;
  std::string file_;
  std::vector<std::string> columns_;
  std::vector<std::string> fields_;
  int line_ = 0;
};

class VnlogTable {
 public:
  // Throws InputError naming the file (and line) when it cannot be read or is malformed.
  static VnlogTable read(const std::string& path);
  // `display_name` names the stream in errors, e.g. "<stdin>".
  static VnlogTable read(std::istream& in, const std::string& display_name);

  const std::string& file() const { return file_; }
  const std::vector<std::string>& column_names() const { return columns_; }
  std::size_t num_rows() const { return lines_.size(); }

  bool has_column(const std::string& name) const;
  // The column's index; throws InputError naming the file when there is no such column.
  std::size_t column(const std::string& name) const;
  // The indices of the named columns, in the order asked; throws for the first missing one.
  std::vector<std::size_t> columns(const std::vector<std::string>& names) const;

  // The field as written, and its line in the file.
  const std::string& text(std::size_t row, std::size_t column) const;
  int line(std::size_t row) const { return lines_[row]; }
  static bool is_missing(const std::string& field) { return field == "-"; }

  // The field as a number (NaN when missing); throws InputError "FILE:LINE: column 'c': ...".
  double number(std::size_t row, std::size_t column) const;
  // Whole columns, by name.
  std::vector<double> numbers(const std::string& column_name) const;
  std::vector<std::string> texts(const std::string& column_name) const;

 private:
  static VnlogTable read(VnlogReader* reader);

  std::string file_;
  std::vector<std::string> columns_;
  std::vector<std::string> fields_;  // row-major, columns_.size() per row
  std::vector<int> lines_;
};

// Whether `text` can be one field: no whitespace, which would split it, and no '#', which would
// end its row.
bool fits_vnlog_field(const std::string& text);
// `text` made a field: each such character '_', empty text '-' (a missing value).
std::string as_vnlog_field(std::string text);

// Writes a table: the header at construction, then rows. Numbers are written with the shortest
// text that reads back exactly; NaN as '-'.
class VnlogWriter {
 public:
  VnlogWriter(std::ostream& out, std::vector<std::string> columns);

  void comment(const std::string& text);
  // Throws std::invalid_argument when the row's size is not the number of columns.
  void row(const std::vector<double>& values);
  // Fields written as given (a string column, or numbers already formatted); empty -> '-'. Throws
  // std::invalid_argument for a field that does not fit (fits_vnlog_field).
  void row_texts(const std::vector<std::string>& fields);

  static std::string field(double value);

 private:
  std::ostream& out_;
  std::size_t num_columns_;
};

}  // namespace omnisfm::io
