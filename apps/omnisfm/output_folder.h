#pragma once
// A result folder written whole or not at all: the verb writes into a temporary folder beside
// the target, which replaces the target only once complete.

#include <functional>
#include <string>

namespace omnisfm::app {

// Throws io::InputError when the folder's parent is not a writable folder; rethrows what `write`
// throws, after removing the temporary folder.
void write_folder(const std::string& dir, const std::function<void(const std::string&)>& write);

}  // namespace omnisfm::app
