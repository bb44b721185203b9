#include "omnisfm/io/vnlog.h"

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

}  // namespace

VnlogTable VnlogTable::read(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    throw InputError(path, 0, "is a folder, not a file");
  }
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open the file");
  return read(in, path);
}

VnlogTable VnlogTable::read(std::istream& in, const std::string& display_name) {
  VnlogTable table;
  table.file_ = display_name;
  bool have_header = false;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (is_blank(text)) continue;
    const std::string content = from_first_nonblank(text);
    if (content.front() == '#') {
      if (have_header || content.rfind("##", 0) == 0 || content.rfind("#!", 0) == 0) continue;
      std::vector<std::string> names = split(content.substr(1));
      if (names.empty()) continue;
      for (std::size_t i = 0; i < names.size(); ++i) {
        for (std::size_t j = 0; j < i; ++j) {
          if (names[i] == names[j]) {
            throw InputError(display_name, line, "column '" + names[i] + "' appears twice");
          }
        }
      }
      table.columns_ = std::move(names);
      have_header = true;
      continue;
    }
    if (!have_header) {
      throw InputError(display_name, line, "data before the '# name name ...' header line");
    }
    std::vector<std::string> fields = split(content);
    if (fields.size() != table.columns_.size()) {
      throw InputError(display_name, line,
                       "expected " + std::to_string(table.columns_.size()) + " fields, found " +
                           std::to_string(fields.size()));
    }
    for (std::string& field : fields) table.fields_.push_back(std::move(field));
    table.lines_.push_back(line);
  }
  if (in.bad()) throw InputError(display_name, line, "read error");
  if (!have_header) throw InputError(display_name, 0, "no '# name name ...' header line");
  return table;
}

bool VnlogTable::has_column(const std::string& name) const {
  for (const std::string& column_name : columns_) {
    if (column_name == name) return true;
  }
  return false;
}

std::size_t VnlogTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (columns_[i] == name) return i;
  }
  std::string present;
  for (const std::string& column_name : columns_) present += " " + column_name;
  throw InputError(file_, 0, "no column '" + name + "' (columns:" + present + ")");
}

std::vector<std::size_t> VnlogTable::columns(const std::vector<std::string>& names) const {
  std::vector<std::size_t> indices;
  for (const std::string& name : names) indices.push_back(column(name));
  return indices;
}

const std::string& VnlogTable::text(std::size_t row, std::size_t column) const {
  return fields_[row * columns_.size() + column];
}

double VnlogTable::number(std::size_t row, std::size_t column) const {
  const std::string& field = text(row, column);
  if (is_missing(field)) return std::numeric_limits<double>::quiet_NaN();
  double value = 0;
  if (!parse_double(field, &value)) {
    throw InputError(file_, lines_[row],
                     "column '" + columns_[column] + "': '" + field + "' is not a number");
  }
  return value;
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

void VnlogWriter::row_texts(const std::vector<std::string>& fields) {
  if (fields.size() != num_columns_) {
    throw std::invalid_argument("vnlog row of " + std::to_string(fields.size()) +
                                " fields for " + std::to_string(num_columns_) + " columns");
  }
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (fields[i].find_first_of(" \t\r\n") != std::string::npos) {
      throw std::invalid_argument("vnlog field '" + fields[i] + "' contains whitespace");
    }
    if (i) out_ << ' ';
    out_ << (fields[i].empty() ? "-" : fields[i]);
  }
  out_ << '\n';
}

}  // namespace omnisfm::io
