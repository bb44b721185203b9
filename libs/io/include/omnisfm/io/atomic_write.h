#pragma once
// Writing a file so that it is never seen half-written: the content goes to a temporary file in
// the same folder, renamed over the target only once complete. On failure the target is left as
// it was and the temporary file is removed.

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

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

// Marks a folder write_folder_atomically wrote, so that a later run may replace it whole.
inline constexpr const char* kWrittenFolderMarker = ".omnisfm-output";

// `given` as a folder's path: absolute, normalised, without a trailing separator ("out/" and
// "out" are one folder; "." is the working folder by its name).
std::filesystem::path folder_path(const std::string& given);

// Whether `path` is `folder` or lies inside it, links resolved (weakly_canonical: either may be
// missing).
bool lies_within(const std::filesystem::path& path, const std::filesystem::path& folder);

// Throws InputError naming `path` ("cannot write here: the folder FOLDER does not exist", "... is
// not a folder", "... is not writable", or why it cannot be searched) unless `folder`, where
// `path` goes, is a folder this process may write in.
void require_writable_folder(const std::string& path, const std::filesystem::path& folder);

// What write_folder_atomically(dir) would refuse or lose, checked before a verb's work (the
// write checks the folder again): throws InputError naming `dir` when the path is empty, names a
// file, or lies in a folder that is missing or not writable; when the folder exists holding
// anything that write_folder_atomically did not write there (a folder of other files is not an
// output to replace); and when one of `inputs` (files the run reads; empty entries are skipped)
// lies inside it, where the replacement would delete it.
void check_folder_replaceable(const std::string& dir, const std::vector<std::string>& inputs = {});

// A folder written whole or not at all: `write` fills a temporary folder beside `dir` (it receives
// its path), which then replaces `dir` in one atomic swap, so that `dir` is at every moment the
// earlier folder or the new one; what killed writers left beside it goes first. The new folder
// holds kWrittenFolderMarker. Throws InputError as check_folder_replaceable (without inputs);
// rethrows what `write` throws, after removing the temporary folder.
void write_folder_atomically(const std::string& dir,
                             const std::function<void(const std::string& folder)>& write);

}  // namespace omnisfm::io
