#pragma once
// INI files in MRPT's CConfigFile syntax:
//   [section]
//   key = value      # a trailing comment
//   ; a whole-line comment (';' or '#')
// Keys before the first [section] belong to the section named "". A section may be reopened
// further down; a key given twice in one section is an error. Keys and section names are
// case-sensitive. Every entry keeps its line so that callers can point at it in errors.

#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace omnisfm::io {

// "from LOW to HIGH" ("a finite number of at least LOW" where high is the largest double), and
// " (or 0: off)" with zero_off: what IniSection::get_within asks for.
std::string range_phrase(double low, double high, bool zero_off);
// "" where value lies from low to high (or is 0 with zero_off), else "must be RANGE: MEANING".
std::string range_problem(double value, double low, double high, bool zero_off,
                          const std::string& meaning);

struct IniEntry {
  std::string key;
  std::string value;
  int line = 0;  // 0 for entries added in memory
};

class IniSection {
 public:
  IniSection(std::string file, std::string name, int line);

  const std::string& name() const { return name_; }
  const std::string& file() const { return file_; }
  // Line of the first [name] header; 0 for the "" section or one built in memory.
  int line() const { return line_; }
  const std::vector<IniEntry>& entries() const { return entries_; }

  bool has(const std::string& key) const;
  // The key's line, or the section's line when the key is absent.
  int line_of(const std::string& key) const;

  // Typed getters mark the key as read. They throw InputError naming the file, the key and its
  // line (the section's line for a missing key) when the key is absent or its value malformed.
  std::string get_string(const std::string& key) const;
  double get_double(const std::string& key) const;
  int get_int(const std::string& key) const;
  // Whitespace-separated numbers, as many as there are.
  std::vector<double> get_doubles(const std::string& key) const;
  // As above, with the value used when the key is absent.
  std::string get_string(const std::string& key, const std::string& fallback) const;
  double get_double(const std::string& key, double fallback) const;
  std::vector<double> get_doubles(const std::string& key,
                                  const std::vector<double>& fallback) const;
  // A finite number > 0 (>= 0 with zero_ok), or the fallback when absent; fails naming the key
  // otherwise. The _int form takes whole numbers only.
  double get_positive(const std::string& key, double fallback, bool zero_ok = false) const;
  int get_positive_int(const std::string& key, int fallback, bool zero_ok = false) const;
  // A number from low to high (or exactly 0 with zero_off: the setting off), or the fallback when
  // absent (not judged: it is the caller's); fails naming the key, the range and `meaning` (why
  // values beyond say nothing). A high of the largest double asks only for a finite number.
  double get_within(const std::string& key, double fallback, double low, double high,
                    const std::string& meaning, bool zero_off = false) const;
  // 1 or 0, true or false, yes or no, on or off (any case), or the fallback when absent.
  bool get_flag(const std::string& key, bool fallback) const;

  // Entries no getter has read, in file order: what the caller did not expect.
  std::vector<IniEntry> unread() const;

  // Throws InputError at the key's line (the section's when absent): "key 'KEY': message".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  // Adds a key, or replaces its value. Throws std::invalid_argument for a value that would not
  // read back (a newline, '#' or ';' in it) or an empty key.
  void set(const std::string& key, const std::string& value);

 private:
  friend class IniFile;
  // Adds a parsed entry, throwing InputError when the key is already there.
  void add_parsed(IniEntry entry);
  const IniEntry& require(const std::string& key) const;
  const IniEntry* find(const std::string& key) const;

  std::string file_;
  std::string name_;
  int line_;
  std::vector<IniEntry> entries_;
  std::map<std::string, std::size_t> index_;
  mutable std::vector<bool> read_;
};

class IniFile {
 public:
  // An empty file in memory; `file` names it in errors.
  explicit IniFile(std::string file = "<memory>");

  // Throws InputError when the file cannot be opened or has a malformed line.
  static IniFile read(const std::string& path);
  // `display_name` names the stream in errors, e.g. "<stdin>".
  static IniFile parse(std::istream& in, const std::string& display_name);

  const std::string& file() const { return file_; }
  const std::vector<IniSection>& sections() const { return sections_; }
  bool has_section(const std::string& name) const;
  // Throws InputError when there is no such section.
  const IniSection& section(const std::string& name) const;
  // The section, created at the end when absent.
  IniSection& add_section(const std::string& name);

  // The "" section first (without a header), then every other one in order.
  void write(std::ostream& out) const;

 private:
  std::string file_;
  std::vector<IniSection> sections_;
};

}  // namespace omnisfm::io
