#pragma once
// The error for bad user input: a file (or "<stdin>"), the line it is on (0 when the problem is
// not tied to a line) and what is wrong. what() reads "FILE:LINE: message", or "FILE: message",
// made printable: text quoted from a damaged file may hold any bytes.

#include <stdexcept>
#include <string>

namespace omnisfm::io {

// `text` with every byte that is not part of valid UTF-8, and every control character but tab and
// newline, written as \xNN. Printable text comes back unchanged, so applying it twice is applying
// it once.
std::string printable_text(const std::string& text);

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, std::string message);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_;
  std::string message_;
};

}  // namespace omnisfm::io
