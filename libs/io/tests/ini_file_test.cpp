#include "omnisfm/io/ini_file.h"

#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>

#include "omnisfm/io/input_error.h"

namespace omnisfm::io {
namespace {

IniFile parsed(const std::string& text) {
  std::istringstream in(text);
  return IniFile::parse(in, "test.ini");
}

// The InputError message of `action`, or "" when it throws nothing.
template <typename Action>
std::string error_of(Action action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

const char* const kExample =
    "# a whole-line comment\n"      // 1
    "global = 1\n"                  // 2
    "\n"                            // 3
    "[camera]   ; trailing\n"       // 4
    "; another comment\n"           // 5
    "fx = 800   # trailing\n"       // 6
    "  name=equiangular;tail\n"     // 7
    "dist = 0.1 -0.2 0 0 1e-3\n"    // 8
    "count = 12\n"                  // 9
    "empty =\n"                     // 10
    "[other]\n"                     // 11
    "fx = 5\n";                     // 12

TEST(IniFile, ReadsSectionsKeysAndComments) {
  const IniFile ini = parsed(kExample);
  ASSERT_EQ(ini.sections().size(), 3u);
  EXPECT_EQ(ini.section("").get_int("global"), 1);
  const IniSection& camera = ini.section("camera");
  EXPECT_EQ(camera.line(), 4);
  EXPECT_EQ(camera.get_double("fx"), 800);
  EXPECT_EQ(camera.get_string("name"), "equiangular");
  EXPECT_EQ(camera.get_doubles("dist"), (std::vector<double>{0.1, -0.2, 0, 0, 1e-3}));
  EXPECT_EQ(camera.get_int("count"), 12);
  EXPECT_EQ(camera.get_string("empty"), "");
  EXPECT_EQ(camera.line_of("name"), 7);
  EXPECT_EQ(ini.section("other").get_double("fx"), 5);
  EXPECT_TRUE(ini.has_section("other"));
  EXPECT_FALSE(ini.has_section("missing"));
}

TEST(IniFile, FallbacksApplyOnlyToAbsentKeys) {
  const IniFile ini = parsed(kExample);
  const IniSection& camera = ini.section("camera");
  EXPECT_EQ(camera.get_double("fy", 3.0), 3.0);
  EXPECT_EQ(camera.get_double("fx", 3.0), 800);
  EXPECT_EQ(camera.get_string("kind", "none"), "none");
  EXPECT_EQ(camera.get_doubles("k", {1, 2}), (std::vector<double>{1, 2}));
}

TEST(IniFile, ListsUnreadKeysInFileOrder) {
  const IniFile ini = parsed(kExample);
  const IniSection& camera = ini.section("camera");
  camera.get_double("fx");
  camera.get_int("count");
  const std::vector<IniEntry> unread = camera.unread();
  ASSERT_EQ(unread.size(), 3u);
  EXPECT_EQ(unread[0].key, "name");
  EXPECT_EQ(unread[0].line, 7);
  EXPECT_EQ(unread[1].key, "dist");
  EXPECT_EQ(unread[2].key, "empty");
}

TEST(IniFile, DuplicateKeyNamesBothLines) {
  const std::string message = error_of([] { parsed("[a]\nx = 1\ny = 2\nx = 3\n"); });
  EXPECT_NE(message.find("test.ini:4:"), std::string::npos) << message;
  EXPECT_NE(message.find("'x'"), std::string::npos) << message;
  EXPECT_NE(message.find("line 2"), std::string::npos) << message;
}

TEST(IniFile, ReopenedSectionKeepsItsKeys) {
  const IniFile ini = parsed("[a]\nx = 1\n[b]\ny = 2\n[a]\nz = 3\n");
  EXPECT_EQ(ini.section("a").get_double("z"), 3);
  EXPECT_EQ(ini.section("a").line(), 1);
  EXPECT_NE(error_of([] { parsed("[a]\nx = 1\n[b]\n[a]\nx = 2\n"); }).find("test.ini:5:"),
            std::string::npos);
}

TEST(IniFile, MalformedLinesAreErrorsWithTheirLine) {
  EXPECT_NE(error_of([] { parsed("[a]\njust words\n"); }).find("test.ini:2:"), std::string::npos);
  EXPECT_NE(error_of([] { parsed("\n[a\n"); }).find("test.ini:2:"), std::string::npos);
  EXPECT_NE(error_of([] { parsed("[]\n"); }).find("test.ini:1:"), std::string::npos);
  EXPECT_NE(error_of([] { parsed("[a]\n = 3\n"); }).find("test.ini:2:"), std::string::npos);
}

TEST(IniFile, TypedGettersNameFileKeyAndLine) {
  const IniFile ini = parsed("[a]\n\nx = abc\nn = 2.5\nv = 1 two 3\n");
  const IniSection& a = ini.section("a");
  std::string message = error_of([&] { a.get_double("x"); });
  EXPECT_NE(message.find("test.ini:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("'x'"), std::string::npos) << message;
  EXPECT_NE(message.find("abc"), std::string::npos) << message;

  message = error_of([&] { a.get_int("n"); });
  EXPECT_NE(message.find("test.ini:4:"), std::string::npos) << message;
  EXPECT_NE(message.find("'n'"), std::string::npos) << message;

  message = error_of([&] { a.get_doubles("v"); });
  EXPECT_NE(message.find("test.ini:5:"), std::string::npos) << message;
  EXPECT_NE(message.find("two"), std::string::npos) << message;

  // A missing key points at its section.
  message = error_of([&] { a.get_double("missing"); });
  EXPECT_NE(message.find("test.ini:1:"), std::string::npos) << message;
  EXPECT_NE(message.find("'missing'"), std::string::npos) << message;
  EXPECT_NE(message.find("[a]"), std::string::npos) << message;
}

TEST(IniFile, PositiveGettersRefuseZeroInfinityAndFractions) {
  const IniFile ini = parsed("[a]\nzero = 0\nfar = inf\nhalf = 2.5\ncount = 3\n");
  const IniSection& a = ini.section("a");
  EXPECT_NE(error_of([&] { a.get_positive("zero", 1); }).find("test.ini:2:"), std::string::npos);
  EXPECT_EQ(a.get_positive("zero", 1, true), 0);
  EXPECT_NE(error_of([&] { a.get_positive("far", 1); }).find("test.ini:3:"), std::string::npos);
  EXPECT_NE(error_of([&] { a.get_positive_int("half", 1); }).find("test.ini:4:"),
            std::string::npos);
  EXPECT_EQ(a.get_positive_int("count", 1), 3);
  EXPECT_EQ(a.get_positive_int("absent", 7), 7);
  EXPECT_NE(error_of([&] { a.get_positive_int("zero", 1); }).find("test.ini:2:"),
            std::string::npos);
}

// A number within its range, or 0 where 0 is off; the range is the file's to meet, so an absent
// key gives the caller's fallback as it is.
TEST(IniFile, RangedGetterNamesTheRangeAndWhy) {
  const IniFile ini = parsed("[a]\nzero = 0\nfar = 1e308\nnear = 0.5\nword = x\n");
  const IniSection& a = ini.section("a");
  EXPECT_EQ(a.get_within("near", 7, 0.1, 1, "metres"), 0.5);
  EXPECT_EQ(a.get_within("zero", 7, 0.1, 1, "metres", true), 0);
  EXPECT_EQ(error_of([&] { a.get_within("zero", 7, 0.1, 1, "metres"); }),
            "test.ini:2: key 'zero': must be from 0.1 to 1: metres");
  EXPECT_EQ(error_of([&] { a.get_within("far", 7, 0.1, 1, "metres", true); }),
            "test.ini:3: key 'far': must be from 0.1 to 1 (or 0: off): metres");
  EXPECT_EQ(error_of([&] { a.get_within("near", 7, 1, std::numeric_limits<double>::max(), "x"); }),
            "test.ini:4: key 'near': must be a finite number of at least 1: x");
  EXPECT_NE(error_of([&] { a.get_within("word", 7, 0.1, 1, "metres"); }).find("test.ini:5:"),
            std::string::npos);
  EXPECT_EQ(a.get_within("absent", 7, 0.1, 1, "metres"), 7);
}

TEST(IniFile, FlagsReadAsWordsOrDigits) {
  const IniFile ini = parsed("[a]\nb = false\nc = 1\nd = Yes\ne = off\nf = 2\ng = maybe\n");
  const IniSection& a = ini.section("a");
  EXPECT_FALSE(a.get_flag("b", true));
  EXPECT_TRUE(a.get_flag("c", false));
  EXPECT_TRUE(a.get_flag("d", false));
  EXPECT_FALSE(a.get_flag("e", true));
  EXPECT_TRUE(a.get_flag("absent", true));
  EXPECT_NE(error_of([&] { a.get_flag("f", true); }).find("test.ini:6:"), std::string::npos);
  EXPECT_NE(error_of([&] { a.get_flag("g", true); }).find("test.ini:7: key 'g': 'maybe'"),
            std::string::npos);
}

TEST(IniFile, MissingSectionAndFileAreErrors) {
  const IniFile ini = parsed("[a]\n");
  const std::string message = error_of([&] { ini.section("b"); });
  EXPECT_EQ(message, "test.ini: no [b] section");
  EXPECT_NE(error_of([] { IniFile::read("/nonexistent/x.ini"); }).find("/nonexistent/x.ini"),
            std::string::npos);
}

TEST(IniFile, WritesWhatItReadsBack) {
  IniFile ini("out.ini");
  ini.add_section("second").set("b", "2");
  IniSection& first = ini.add_section("first");
  first.set("a", "1.5");
  first.set("path", "profile.vnl");
  first.set("a", "2.5");
  ini.add_section("").set("top", "x");
  std::ostringstream out;
  ini.write(out);
  EXPECT_EQ(out.str(), "top = x\n\n[second]\nb = 2\n\n[first]\na = 2.5\npath = profile.vnl\n");

  const IniFile back = parsed(out.str());
  EXPECT_EQ(back.section("first").get_double("a"), 2.5);
  EXPECT_EQ(back.section("first").get_string("path"), "profile.vnl");
  EXPECT_EQ(back.section("").get_string("top"), "x");

  EXPECT_THROW(first.set("c", "has # comment"), std::invalid_argument);
  EXPECT_THROW(first.set("", "1"), std::invalid_argument);
}

TEST(InputError, FormatsFileLineAndMessage) {
  EXPECT_STREQ(InputError("a.ini", 3, "bad").what(), "a.ini:3: bad");
  EXPECT_STREQ(InputError("a.ini", 0, "bad").what(), "a.ini: bad");
  const InputError error("f", 7, "m");
  EXPECT_EQ(error.file(), "f");
  EXPECT_EQ(error.line(), 7);
  EXPECT_EQ(error.message(), "m");
}

}  // namespace
}  // namespace omnisfm::io
