#include "omnisfm/io/vnlog.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <istream>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"

namespace omnisfm::io {
namespace {

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> fields;
  std::istringstream in(text);
  std::string field;
  while (in >> field) fields.push_back(field);
  return fields;
}

bool is_blank(const std::string& text) {
  return text.find_first_not_of(" \t\r\f\v") == std::string::npos;
}

// The text after leading whitespace, or "" for a blank line.
std::string from_first_nonblank(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\f\v");
  return first == std::string::npos ? "" : text.substr(first);
}

std::size_t column_index(const std::string& file, const std::vector<std::string>& columns,
                         const std::string& name) {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  std::string present;
  for (const std::string& column_name : columns) present += " " + column_name;
  throw InputError(file, 0, "no column '" + name + "' (columns:" + present + ")");
}

std::vector<std::size_t> column_indices(const std::string& file,
                                        const std::vector<std::string>& columns,
                                        const std::vector<std::string>& names) {
  std::vector<std::size_t> indices;
  for (const std::string& name : names) indices.push_back(column_index(file, columns, name));
  return indices;
}

double number_of(const std::string& file, int line, const std::string& column,
                 const std::string& field) {
  if (VnlogTable::is_missing(field)) return std::numeric_limits<double>::quiet_NaN();
  double value = 0;
  if (!parse_double(field, &value))
    throw InputError(file, line,
                     "column '" + column + "': '" + field + "' " + not_a_double_reason(field));
  return value;
}

}  // namespace

VnlogReader::VnlogReader(const std::string& path) : file_(path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) throw InputError(path, 0, "is a folder, not a file");
  owned_ = std::make_unique<std::ifstream>(path);
  if (!*owned_) throw InputError(path, 0, "cannot open the file");
  in_ = owned_.get();
  read_header();
}

VnlogReader::VnlogReader(std::istream& in, const std::string& display_name)
    : in_(&in), file_(display_name) {
  read_header();
}

VnlogReader::~VnlogReader() = default;

void VnlogReader::read_header() {
  std::string text;
  while (std::getline(*in_, text)) {
    ++line_;
    if (is_blank(text)) continue;
    const std::string content = from_first_nonblank(text);
    if (content.front() != '#')
      throw InputError(file_, line_, "data before the '# name name ...' header line");
    if (content.rfind("##", 0) == 0 || content.rfind("#!", 0) == 0) continue;
    std::vector<std::string> names = split(content.substr(1));
    if (names.empty()) continue;
    for (std::size_t i = 0; i < names.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (names[i] == names[j])
          throw InputError(file_, line_, "column '" + names[i] + "' appears twice");
    columns_ = std::move(names);
    return;
  }
  if (in_->bad()) throw InputError(file_, line_, "read error");
  throw InputError(file_, 0, "no '# name name ...' header line");
}

bool VnlogReader::next() {
  std::string text;
  while (std::getline(*in_, text)) {
    ++line_;
    if (is_blank(text)) continue;
    const std::string content = from_first_nonblank(text);
    if (content.front() == '#') continue;  // comments, after the header
    // As vnlog's own readers take it: a '#' ends a row's fields, the rest is a comment.
    fields_ = split(content.substr(0, content.find('#')));
    if (fields_.size() != columns_.size())
      throw InputError(file_, line_,
                       "expected " + std::to_string(columns_.size()) + " fields, found " +
                           std::to_string(fields_.size()));
    return true;
  }
  if (in_->bad()) throw InputError(file_, line_, "read error");
  return false;
}

std::size_t VnlogReader::column(const std::string& name) const {
  return column_index(file_, columns_, name);
}

std::vector<std::size_t> VnlogReader::columns(const std::vector<std::string>& names) const {
  return column_indices(file_, columns_, names);
}

double VnlogReader::number(std::size_t column) const {
  return number_of(file_, line_, columns_[column], fields_[column]);
}

VnlogTable VnlogTable::read(const std::string& path) {
  VnlogReader reader(path);
  return read(&reader);
}

VnlogTable VnlogTable::read(std::istream& in, const std::string& display_name) {
  VnlogReader reader(in, display_name);
  return read(&reader);
}

VnlogTable VnlogTable::read(VnlogReader* reader) {
  VnlogTable table;
  table.file_ = reader->file();
  table.columns_ = reader->column_names();
  while (reader->next()) {
    for (const std::string& field : reader->fields()) table.fields_.push_back(field);
    table.lines_.push_back(reader->line());
  }
  return table;
}

bool VnlogTable::has_column(const std::string& name) const {
  for (const std::string& column_name : columns_) {
    if (column_name == name) return true;
  }
  return false;
}

std::size_t VnlogTable::column(const std::string& name) const {
  return column_index(file_, columns_, name);
}

std::vector<std::size_t> VnlogTable::columns(const std::vector<std::string>& names) const {
  return column_indices(file_, columns_, names);
}

const std::string& VnlogTable::text(std::size_t row, std::size_t column) const {
  return fields_[row * columns_.size() + column];
}

double VnlogTable::number(std::size_t row, std::size_t column) const {
  return number_of(file_, lines_[row], columns_[column], text(row, column));
}

std::vector<double> VnlogTable::numbers(const std::string& column_name) const {
  const std::size_t index = column(column_name);
  std::vector<double> values(num_rows());
  for (std::size_t row = 0; row < num_rows(); ++row) values[row] = number(row, index);
  return values;
}

std::vector<std::string> VnlogTable::texts(const std::string& column_name) const {
  const std::size_t index = column(column_name);
  std::vector<std::string> values(num_rows());
  for (std::size_t row = 0; row < num_rows(); ++row) values[row] = text(row, index);
  return values;
}

VnlogWriter::VnlogWriter(std::ostream& out, std::vector<std::string> columns)
    : out_(out), num_columns_(columns.size()) {
  if (columns.empty()) throw std::invalid_argument("a vnlog table needs at least one column");
  out_ << '#';
  for (const std::string& name : columns) {
    if (name.empty() || name.find_first_of(" \t\r\n#") != std::string::npos) {
      throw std::invalid_argument("invalid vnlog column name '" + name + "'");
    }
    out_ << ' ' << name;
  }
  out_ << '\n';
}

void VnlogWriter::comment(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) out_ << "## " << line << '\n';
}

std::string VnlogWriter::field(double value) {
  return std::isnan(value) ? std::string("-") : format_double(value);
}

void VnlogWriter::row(const std::vector<double>& values) {
  if (values.size() != num_columns_) {
    throw std::invalid_argument("vnlog row of " + std::to_string(values.size()) +
                                " values for " + std::to_string(num_columns_) + " columns");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) out_ << ' ';
    out_ << field(values[i]);
  }
  out_ << '\n';
}

namespace {

// Splits a field (what `istream >> std::string` stops at) or ends its row.
bool breaks_vnlog_field(char c) { return std::isspace(static_cast<unsigned char>(c)) || c == '#'; }

}  // namespace

bool fits_vnlog_field(const std::string& text) {
  return std::none_of(text.begin(), text.end(), breaks_vnlog_field);
}

std::string as_vnlog_field(std::string text) {
  std::replace_if(text.begin(), text.end(), breaks_vnlog_field, '_');
  return text.empty() ? "-" : text;
}

void VnlogWriter::row_texts(const std::vector<std::string>& fields) {
  if (fields.size() != num_columns_) {
    throw std::invalid_argument("vnlog row of " + std::to_string(fields.size()) +
                                " fields for " + std::to_string(num_columns_) + " columns");
  }
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!fits_vnlog_field(fields[i])) {
      throw std::invalid_argument("vnlog field '" + fields[i] + "' contains whitespace or '#'");
    }
    if (i) out_ << ' ';
    out_ << (fields[i].empty() ? "-" : fields[i]);
  }
  out_ << '\n';
}

}  // namespace omnisfm::io
