#include "omnisfm/io/ini_file.h"

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
#include <utility>

#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"

namespace omnisfm::io {
namespace {

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\f\v");
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(" \t\r\f\v");
  return text.substr(first, last - first + 1);
}

std::string without_comment(const std::string& text) {
  return text.substr(0, text.find_first_of("#;"));
}

std::string in_quotes(const std::string& text) { return "'" + text + "'"; }

}  // namespace

IniSection::IniSection(std::string file, std::string name, int line)
    : file_(std::move(file)), name_(std::move(name)), line_(line) {}

const IniEntry* IniSection::find(const std::string& key) const {
  const auto found = index_.find(key);
  if (found == index_.end()) return nullptr;
  read_[found->second] = true;
  return &entries_[found->second];
}

bool IniSection::has(const std::string& key) const { return index_.count(key) != 0; }

int IniSection::line_of(const std::string& key) const {
  const auto found = index_.find(key);
  return found == index_.end() ? line_ : entries_[found->second].line;
}

void IniSection::fail(const std::string& key, const std::string& message) const {
  throw InputError(file_, line_of(key), "key " + in_quotes(key) + ": " + message);
}

const IniEntry& IniSection::require(const std::string& key) const {
  const IniEntry* entry = find(key);
  if (!entry) {
    const std::string where = name_.empty() ? "the file" : "section [" + name_ + "]";
    throw InputError(file_, line_, "missing key " + in_quotes(key) + " in " + where);
  }
  return *entry;
}

std::string IniSection::get_string(const std::string& key) const { return require(key).value; }

double IniSection::get_double(const std::string& key) const {
  const IniEntry& entry = require(key);
  double value = 0;
  if (!parse_double(entry.value, &value))
    fail(key, in_quotes(entry.value) + " " + not_a_double_reason(entry.value));
  return value;
}

int IniSection::get_int(const std::string& key) const {
  const IniEntry& entry = require(key);
  int value = 0;
  if (!parse_int(entry.value, &value)) fail(key, in_quotes(entry.value) + " is not an integer");
  return value;
}

std::vector<double> IniSection::get_doubles(const std::string& key) const {
  const IniEntry& entry = require(key);
  std::vector<double> values;
  std::istringstream fields(entry.value);
  std::string field;
  while (fields >> field) {
    double value = 0;
    if (!parse_double(field, &value))
      fail(key, in_quotes(field) + " " + not_a_double_reason(field));
    values.push_back(value);
  }
  return values;
}

std::string IniSection::get_string(const std::string& key, const std::string& fallback) const {
  return has(key) ? get_string(key) : fallback;
}

double IniSection::get_double(const std::string& key, double fallback) const {
  return has(key) ? get_double(key) : fallback;
}

std::vector<double> IniSection::get_doubles(const std::string& key,
                                            const std::vector<double>& fallback) const {
  return has(key) ? get_doubles(key) : fallback;
}

double IniSection::get_positive(const std::string& key, double fallback, bool zero_ok) const {
  const double v = get_double(key, fallback);
  if (!std::isfinite(v)) fail(key, "must be a finite number");
  if (!(zero_ok ? v >= 0 : v > 0)) fail(key, zero_ok ? "must be >= 0" : "must be > 0");
  return v;
}

int IniSection::get_positive_int(const std::string& key, int fallback, bool zero_ok) const {
  const int v = has(key) ? get_int(key) : fallback;
  if (!(zero_ok ? v >= 0 : v > 0)) fail(key, zero_ok ? "must be >= 0" : "must be > 0");
  return v;
}

std::string range_phrase(double low, double high, bool zero_off) {
  const std::string range = high < std::numeric_limits<double>::max()
                                ? "from " + format_double(low) + " to " + format_double(high)
                                : "a finite number of at least " + format_double(low);
  return range + (zero_off ? " (or 0: off)" : "");
}

std::string range_problem(double value, double low, double high, bool zero_off,
                          const std::string& meaning) {
  if ((zero_off && value == 0) || (value >= low && value <= high)) return "";
  return "must be " + range_phrase(low, high, zero_off) + ": " + meaning;
}

double IniSection::get_within(const std::string& key, double fallback, double low, double high,
                              const std::string& meaning, bool zero_off) const {
  // The range is the file's to meet: a fallback set in code is the caller's.
  if (!has(key)) return fallback;
  const double v = get_double(key);
  if (const std::string problem = range_problem(v, low, high, zero_off, meaning); !problem.empty())
    fail(key, problem);
  return v;
}

bool IniSection::get_flag(const std::string& key, bool fallback) const {
  if (!has(key)) return fallback;
  std::string value = get_string(key);
  for (char& c : value) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (value == "1" || value == "true" || value == "yes" || value == "on") return true;
  if (value == "0" || value == "false" || value == "no" || value == "off") return false;
  fail(key, "'" + get_string(key) + "' must be 1 or 0 (true or false, yes or no, on or off)");
}

std::vector<IniEntry> IniSection::unread() const {
  std::vector<IniEntry> result;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (!read_[i]) result.push_back(entries_[i]);
  }
  return result;
}

void IniSection::set(const std::string& key, const std::string& value) {
  if (trimmed(key).empty() || key != trimmed(key) ||
      key.find_first_of("=#;[]\n") != std::string::npos) {
    throw std::invalid_argument("invalid INI key " + in_quotes(key));
  }
  if (value.find_first_of("#;\n\r") != std::string::npos || value != trimmed(value)) {
    throw std::invalid_argument("INI value " + in_quotes(value) + " of key " + in_quotes(key) +
                                " would not read back");
  }
  const auto found = index_.find(key);
  if (found != index_.end()) {
    entries_[found->second].value = value;
    return;
  }
  index_[key] = entries_.size();
  entries_.push_back({key, value, 0});
  read_.push_back(false);
}

void IniSection::add_parsed(IniEntry entry) {
  const auto found = index_.find(entry.key);
  if (found != index_.end()) {
    throw InputError(file_, entry.line,
                     "duplicate key " + in_quotes(entry.key) + " (first given on line " +
                         std::to_string(entries_[found->second].line) + ")");
  }
  index_[entry.key] = entries_.size();
  entries_.push_back(std::move(entry));
  read_.push_back(false);
}

IniFile::IniFile(std::string file) : file_(std::move(file)) {}

IniFile IniFile::read(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    throw InputError(path, 0, "is a folder, not a file");
  }
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open the file");
  return parse(in, path);
}

IniFile IniFile::parse(std::istream& in, const std::string& display_name) {
  IniFile ini(display_name);
  IniSection* section = nullptr;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    const std::string content = trimmed(without_comment(text));
    if (content.empty()) continue;
    if (content.front() == '[') {
      if (content.back() != ']') throw InputError(display_name, line, "expected '[section]'");
      const std::string name = trimmed(content.substr(1, content.size() - 2));
      if (name.empty()) throw InputError(display_name, line, "empty section name");
      const bool reopened = ini.has_section(name);
      section = &ini.add_section(name);
      if (!reopened) section->line_ = line;
      continue;
    }
    const auto equals = content.find('=');
    if (equals == std::string::npos) {
      throw InputError(display_name, line, "expected 'key = value' or '[section]'");
    }
    std::string key = trimmed(content.substr(0, equals));
    if (key.empty()) throw InputError(display_name, line, "no key before '='");
    if (!section) section = &ini.add_section("");
    section->add_parsed({std::move(key), trimmed(content.substr(equals + 1)), line});
  }
  if (in.bad()) throw InputError(display_name, line, "read error");
  return ini;
}

bool IniFile::has_section(const std::string& name) const {
  for (const IniSection& section : sections_) {
    if (section.name() == name) return true;
  }
  return false;
}

const IniSection& IniFile::section(const std::string& name) const {
  for (const IniSection& section : sections_) {
    if (section.name() == name) return section;
  }
  throw InputError(file_, 0, "no [" + name + "] section");
}

IniSection& IniFile::add_section(const std::string& name) {
  for (IniSection& section : sections_) {
    if (section.name() == name) return section;
  }
  sections_.emplace_back(file_, name, 0);
  return sections_.back();
}

void IniFile::write(std::ostream& out) const {
  bool first = true;
  const auto write_entries = [&out](const IniSection& section) {
    for (const IniEntry& entry : section.entries()) {
      out << entry.key << " = " << entry.value << '\n';
    }
  };
  for (const IniSection& section : sections_) {
    if (section.name().empty()) {
      write_entries(section);
      first = section.entries().empty();
    }
  }
  for (const IniSection& section : sections_) {
    if (section.name().empty()) continue;
    if (!first) out << '\n';
    first = false;
    out << '[' << section.name() << "]\n";
    write_entries(section);
  }
}

}  // namespace omnisfm::io
