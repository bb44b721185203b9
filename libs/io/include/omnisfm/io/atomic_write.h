#pragma once
// Writing a file so that it is never seen half-written: the content goes to a temporary file in
// the same folder, renamed over the target only once complete. On failure the target is left as
// it was and the temporary file is removed.

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>

namespace omnisfm::io {

// `write` receives the temporary file's path (with the target's extension) and must create it.
// Throws std::runtime_error naming `path` when the rename fails; rethrows what `write` throws.
void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary_path)>& write);

// Removes what writers killed before they could clean up left in `folder`: entries named
// prefix + PID + suffix whose process PID no longer runs. Writers call it before they write, so a
// killed run's temporaries last only until the next run.
void remove_abandoned_temporaries(const std::filesystem::path& folder, const std::string& prefix,
                                  const std::string& suffix);

// The same for text written to a stream; a stream error is a std::runtime_error naming `path`.
void write_text_atomically(const std::string& path,
                           const std::function<void(std::ostream& out)>& write);

}  // namespace omnisfm::io
