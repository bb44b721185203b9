#pragma once
// MRPT serialization in memory and in rawlog files, for the plugin's tests: objects as bytes,
// bytes patched in place, rawlogs written uncompressed so that object boundaries are known.

#include <gtest/gtest.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdint>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace omnisfm::mrpt_plugin::testing {

using Bytes = std::vector<std::uint8_t>;

inline Bytes to_bytes(const mrpt::serialization::CSerializable& object) {
  mrpt::io::CMemoryStream buffer;
  auto archive = mrpt::serialization::archiveFrom(buffer);
  archive << object;
  const auto* data = static_cast<const std::uint8_t*>(buffer.getRawBufferData());
  return Bytes(data, data + buffer.getTotalBytesCount());
}

// Throws what MRPT throws for bytes that are not an object.
inline mrpt::serialization::CSerializable::Ptr from_bytes(const Bytes& bytes) {
  mrpt::io::CMemoryStream buffer(bytes.data(), bytes.size());
  auto archive = mrpt::serialization::archiveFrom(buffer);
  return archive.ReadObject();
}

template <typename T>
std::shared_ptr<T> round_trip(const mrpt::serialization::CSerializable& object) {
  return std::dynamic_pointer_cast<T>(from_bytes(to_bytes(object)));
}

// Where `text` first occurs in `bytes`, or bytes.size().
inline std::size_t find(const Bytes& bytes, const std::string& text) {
  const auto same = [](std::uint8_t byte, char c) { return byte == static_cast<std::uint8_t>(c); };
  return static_cast<std::size_t>(
      std::search(bytes.begin(), bytes.end(), text.begin(), text.end(), same) - bytes.begin());
}

// Replaces the first occurrence of `from` by `to` (same length); fails the test when absent.
inline void patch(Bytes* bytes, const std::string& from, const std::string& to) {
  ASSERT_EQ(from.size(), to.size());
  const std::size_t at = find(*bytes, from);
  ASSERT_LT(at, bytes->size()) << "'" << from << "' is not in the bytes";
  std::copy(to.begin(), to.end(), bytes->begin() + static_cast<std::ptrdiff_t>(at));
}

// An object's stored class version: MRPT writes it right after the class name.
inline std::size_t version_byte(const Bytes& bytes, const std::string& class_name) {
  return find(bytes, class_name) + class_name.size();
}

// One per process: ctest --parallel runs tests side by side, each in a process of its own.
inline std::string temporary_path(const std::string& name) {
  return ::testing::TempDir() + "/omnisfm_mrpt_" + std::to_string(::getpid()) + "_" + name;
}

inline void write_file(const std::string& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

inline Bytes read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// An uncompressed rawlog of `objects`; returns the byte offset at which each object starts, and
// the file's size last.
inline std::vector<std::size_t> write_plain_rawlog(
    const std::string& path,
    const std::vector<const mrpt::serialization::CSerializable*>& objects) {
  Bytes file;
  std::vector<std::size_t> offsets;
  for (const auto* object : objects) {
    offsets.push_back(file.size());
    const Bytes bytes = to_bytes(*object);
    file.insert(file.end(), bytes.begin(), bytes.end());
  }
  offsets.push_back(file.size());
  write_file(path, file);
  return offsets;
}

}  // namespace omnisfm::mrpt_plugin::testing
