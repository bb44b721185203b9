#pragma once
// What every reader promises on any bytes: it returns what it read, which then keeps the
// reader's documented guarantees, or it throws io::InputError naming a file and a line that exist,
// in printable text. Anything else (another exception type, an error naming no file or a line
// past the end, a guarantee broken) is a finding: the target aborts, and libFuzzer keeps the
// input that did it.

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <typeinfo>

#include "omnisfm/io/input_error.h"

namespace omnisfm::fuzz {

// A folder of this process's own, made once and emptied at exit.
const std::string& scratch_folder();

// Writes the bytes to `name` inside scratch_folder(), replacing what was there; returns the path.
std::string write_input(const std::uint8_t* data, std::size_t size, const std::string& name);

// Prints "fuzz contract broken: <what>" and aborts.
[[noreturn]] void broken(const std::string& what);

// Aborts unless `condition`; `what` says which guarantee.
inline void require(bool condition, const char* what) {
  if (!condition) broken(what);
}

// Checks an InputError against the contract: a file named, its line 0 or within the file,
// printable text.
void check_input_error(const io::InputError& error);

// Runs `read`; an io::InputError is checked, any other exception is a finding.
template <class Read>
void expect_contract(Read&& read) {
  try {
    read();
  } catch (const io::InputError& error) {
    check_input_error(error);
  } catch (const std::exception& error) {
    broken(std::string("an exception other than io::InputError: ") + typeid(error).name() + ": " +
           error.what());
  }
}

}  // namespace omnisfm::fuzz
