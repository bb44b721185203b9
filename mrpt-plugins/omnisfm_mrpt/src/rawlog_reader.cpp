#include "omnisfm/mrpt_plugin/rawlog_reader.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <regex>

#include "omnisfm/io/input_error.h"

namespace omnisfm::mrpt_plugin {
namespace {

// The class of the outermost object being read when it failed, when MRPT says (it does not when
// the class name itself is cut short).
std::string failed_class(const std::string& text) {
  static const std::regex pattern(R"(parsing typed object '([A-Za-z_][A-Za-z0-9_:]*)' from)");
  std::smatch match;
  return std::regex_search(text, match, pattern) ? match[1].str() : std::string();
}

std::string unregistered_class(const std::string& text) {
  static const std::regex pattern(R"(Stored object has class '([^']*)' which is not registered)");
  std::smatch match;
  return std::regex_search(text, match, pattern) ? match[1].str() : std::string();
}

std::string unknown_version(const std::string& text) {
  static const std::regex pattern(R"(unknown serialization version number: '(-?\d+)')");
  std::smatch match;
  return std::regex_search(text, match, pattern) ? match[1].str() : std::string();
}

}  // namespace

std::string mrpt_error_reason(const std::string& what) {
  // MRPT nests the exceptions of an object's members, each as "Message:  text"; the innermost
  // one says what went wrong.
  static const std::regex message(R"(Message:\s+([^\n]*))");
  std::string last;
  for (auto it = std::sregex_iterator(what.begin(), what.end(), message);
       it != std::sregex_iterator(); ++it)
    last = (*it)[1].str();
  return last.empty() ? what.substr(0, what.find('\n')) : last;
}

std::string describe_damage(const std::string& path, std::size_t index,
                            const std::string& object_class, const std::string& what) {
  const std::string n = std::to_string(index);
  const std::string before = index == 0   ? "nothing before it was read"
                             : index == 1 ? "the 1 object before it was read"
                                          : "the " + n + " objects before it were read";
  return path + ": object " + n + (object_class.empty() ? "" : " (" + object_class + ")") + ": " +
         what + "; " + before;
}

std::string unregistered_class_advice(const std::string& class_name) {
  if (class_name.rfind("omnisfm::", 0) == 0) {
    return "it is one of omnisfm's classes: load the plugin that defines it, libomnisfm_mrpt.so "
           "(rawlog-edit -p /path/to/libomnisfm_mrpt.so; a rawlog from a newer omnisfm needs "
           "that version's plugin)";
  }
  return "load the library that defines it (MRPT tools: -p /path/to/plugin.so)";
}

RawlogReader::RawlogReader(const std::string& path)
    : path_(path), file_(std::make_unique<mrpt::io::CFileGZInputStream>()) {
  std::string why;
  try {
    if (file_->open(path)) return;
  } catch (const std::exception& error) {
    why = std::string(": ") + error.what();
  }
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) why = ": no such file";
  throw io::InputError(path, 0, "cannot open the rawlog" + why);
}

RawlogReader::~RawlogReader() = default;

mrpt::serialization::CSerializable::Ptr RawlogReader::next() {
  while (!finished_) {
    auto archive = mrpt::serialization::archiveFrom(*file_);
    mrpt::serialization::CSerializable::Ptr object;
    try {
      object = archive.ReadObject();
    } catch (const mrpt::serialization::CExceptionEOF&) {
      // MRPT raises this one only at an object boundary: a clean end.
      finished_ = true;
      return nullptr;
    } catch (const std::exception& error) {
      finished_ = true;
      problem_ = describe_failure(error.what());
      return nullptr;
    }
    ++index_;
    if (object) return object;
  }
  return nullptr;
}

std::string RawlogReader::describe_failure(const std::string& mrpt_message) {
  std::string what;
  const std::string unregistered = unregistered_class(mrpt_message);
  const std::string version = unknown_version(mrpt_message);
  if (!unregistered.empty()) {
    what = "its class '" + unregistered + "' is not registered: " +
           unregistered_class_advice(unregistered);
  } else if (!version.empty()) {
    what = "it was stored by a newer version (" + version + ") of its class than this reader knows";
  } else if (file_->checkEOF()) {
    what = "the file ends inside it (truncated)";
  } else {
    what = "it is corrupt (" + mrpt_error_reason(mrpt_message) + ")";
  }
  return describe_damage(path_, index_, failed_class(mrpt_message), what);
}

}  // namespace omnisfm::mrpt_plugin
