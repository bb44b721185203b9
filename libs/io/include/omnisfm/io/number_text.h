#pragma once
// Numbers as text in omnisfm's files: parsing that accepts a whole field or nothing, and the
// shortest text that reads back as the same double.

#include <string>
#include <string_view>

namespace omnisfm::io {

// Parses the whole of `text` (a leading '+' is allowed; "nan" and "inf" are accepted). Returns
// false, leaving *value unchanged, for anything else, including out-of-range values.
bool parse_double(std::string_view text, double* value);
bool parse_int(std::string_view text, int* value);
// Why parse_double refused `text`: "is out of range" for a number beyond a double's (1e400),
// else "is not a number".
std::string not_a_double_reason(std::string_view text);

// The shortest decimal text that parses back to exactly `value` ("0.1", "1e-05", "800").
std::string format_double(double value);

}  // namespace omnisfm::io
