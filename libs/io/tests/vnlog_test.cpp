#include "omnisfm/io/vnlog.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "omnisfm/io/input_error.h"

namespace omnisfm::io {
namespace {

VnlogTable parsed(const std::string& text) {
  std::istringstream in(text);
  return VnlogTable::read(in, "table.vnl");
}

template <typename Action>
std::string error_of(Action action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(Vnlog, ReadsHeaderCommentsAndMissingValues) {
  const VnlogTable table = parsed(
      "#! /usr/bin/something\n"  // 1
      "## produced by a test\n"  // 2
      "\n"                       // 3
      "# x y  z\n"               // 4
      "1 2 3\n"                  // 5
      "# a comment\n"            // 6
      "  4.5 - -6e-1  \n"        // 7
      "\n");
  EXPECT_EQ(table.column_names(), (std::vector<std::string>{"x", "y", "z"}));
  ASSERT_EQ(table.num_rows(), 2u);
  EXPECT_EQ(table.line(0), 5);
  EXPECT_EQ(table.line(1), 7);
  EXPECT_EQ(table.numbers("x"), (std::vector<double>{1, 4.5}));
  EXPECT_EQ(table.number(1, 2), -0.6);
  EXPECT_TRUE(std::isnan(table.number(1, 1)));
  EXPECT_TRUE(VnlogTable::is_missing(table.text(1, 1)));
}

TEST(Vnlog, SelectsColumnsByName) {
  const VnlogTable table = parsed("# filename x y level\nimg0.png 10.5 20 0\nimg1.png - 3 1\n");
  EXPECT_EQ(table.columns({"y", "x"}), (std::vector<std::size_t>{2, 1}));
  EXPECT_TRUE(table.has_column("level"));
  EXPECT_FALSE(table.has_column("z"));
  EXPECT_EQ(table.texts("filename"), (std::vector<std::string>{"img0.png", "img1.png"}));
  EXPECT_EQ(table.numbers("level"), (std::vector<double>{0, 1}));

  const std::string message = error_of([&] { table.columns({"x", "z"}); });
  EXPECT_NE(message.find("table.vnl:"), std::string::npos) << message;
  EXPECT_NE(message.find("'z'"), std::string::npos) << message;
}

TEST(Vnlog, BadNumberNamesFileLineAndColumn) {
  const VnlogTable table = parsed("# x y\n1 2\n\n3 abc\n");
  const std::string message = error_of([&] { table.numbers("y"); });
  EXPECT_NE(message.find("table.vnl:4:"), std::string::npos) << message;
  EXPECT_NE(message.find("'y'"), std::string::npos) << message;
  EXPECT_NE(message.find("abc"), std::string::npos) << message;
  EXPECT_EQ(table.numbers("x"), (std::vector<double>{1, 3}));
}

TEST(Vnlog, TrailingCommentEndsARow) {
  const VnlogTable table = parsed("# x y\n1 2 # measured twice\n3 4#\n");
  ASSERT_EQ(table.num_rows(), 2u);
  EXPECT_EQ(table.numbers("y"), (std::vector<double>{2, 4}));
  // The comment's words are not fields.
  const std::string message = error_of([] { parsed("# x y z\n1 2 # 3\n"); });
  EXPECT_NE(message.find("table.vnl:2: expected 3 fields, found 2"), std::string::npos) << message;
}

TEST(Vnlog, WrongFieldCountIsAnError) {
  std::string message = error_of([] { parsed("# x y z\n1 2 3\n1 2\n"); });
  EXPECT_NE(message.find("table.vnl:3:"), std::string::npos) << message;
  message = error_of([] { parsed("# x y\n1 2 3\n"); });
  EXPECT_NE(message.find("table.vnl:2:"), std::string::npos) << message;
}

TEST(Vnlog, HeaderProblemsAreErrors) {
  EXPECT_EQ(error_of([] { parsed(""); }), "table.vnl: no '# name name ...' header line");
  EXPECT_NE(error_of([] { parsed("## only comments\n1 2\n"); }).find("table.vnl:2:"),
            std::string::npos);
  EXPECT_NE(error_of([] { parsed("# x x\n"); }).find("table.vnl:1:"), std::string::npos);
  EXPECT_NE(error_of([] { VnlogTable::read("/nonexistent/t.vnl"); }).find("/nonexistent/t.vnl"),
            std::string::npos);
  EXPECT_NE(error_of([] { VnlogTable::read("/"); }).find("folder"), std::string::npos);
}

// A damaged header's bytes come back in the message escaped, never raw; UTF-8 stays as it is.
TEST(Vnlog, ErrorsEscapeBytesThatAreNotText) {
  const std::string message =
      error_of([] { parsed("# fr\xff\xfe""ame caf\xc3\xa9 \x1b[2J\n1 2 3\n").numbers("x"); });
  EXPECT_NE(message.find("(columns: fr\\xff\\xfeame caf\xc3\xa9 \\x1b[2J)"), std::string::npos)
      << message;
  EXPECT_EQ(printable_text(message), message);
  EXPECT_EQ(printable_text("\xe0\x80\x80 \xed\xa0\x80 \xf4\x90\x80\x80 \xc3"),
            "\\xe0\\x80\\x80 \\xed\\xa0\\x80 \\xf4\\x90\\x80\\x80 \\xc3");
}

// Row by row, as the table reads the whole: the same fields, lines and errors, the bad row's only
// once it is reached.
TEST(Vnlog, ReaderStreamsRowsWithTheirLines) {
  std::istringstream in("## comment\n# x y\n1 -\n# later comment\n\n3 abc\n4 5 6\n");
  VnlogReader reader(in, "table.vnl");
  EXPECT_EQ(reader.column_names(), (std::vector<std::string>{"x", "y"}));
  ASSERT_TRUE(reader.next());
  EXPECT_EQ(reader.line(), 3);
  EXPECT_EQ(reader.number(reader.column("x")), 1);
  EXPECT_TRUE(std::isnan(reader.number(1)));
  ASSERT_TRUE(reader.next());
  EXPECT_EQ(reader.line(), 6);
  EXPECT_EQ(error_of([&] { reader.number(1); }), "table.vnl:6: column 'y': 'abc' is not a number");
  EXPECT_EQ(error_of([&] { reader.next(); }), "table.vnl:7: expected 2 fields, found 3");
  EXPECT_NE(error_of([&] { reader.columns({"z"}); }).find("no column 'z'"), std::string::npos);
  std::istringstream empty("# a\n");
  VnlogReader no_rows(empty, "empty.vnl");
  EXPECT_FALSE(no_rows.next());
  std::istringstream headless("1 2\n");
  EXPECT_EQ(error_of([&] { VnlogReader r(headless, "h.vnl"); }),
            "h.vnl:1: data before the '# name name ...' header line");
}

TEST(Vnlog, EmptyTableHasColumnsAndNoRows) {
  const VnlogTable table = parsed("# u v\n");
  EXPECT_EQ(table.num_rows(), 0u);
  EXPECT_TRUE(table.numbers("u").empty());
}

TEST(Vnlog, WriterRoundTripsExactlyWithMissingValues) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::ostringstream out;
  VnlogWriter writer(out, {"u", "v"});
  writer.comment("two lines\nof comment");
  writer.row({0.1, 800});
  writer.row({nan, 1.0 / 3.0});
  writer.row({-1e-300, 511.5});
  EXPECT_EQ(out.str(),
            "# u v\n## two lines\n## of comment\n0.1 800\n- 0.3333333333333333\n-1e-300 511.5\n");

  const VnlogTable back = parsed(out.str());
  ASSERT_EQ(back.num_rows(), 3u);
  EXPECT_EQ(back.number(0, 0), 0.1);
  EXPECT_TRUE(std::isnan(back.number(1, 0)));
  EXPECT_EQ(back.number(1, 1), 1.0 / 3.0);
  EXPECT_EQ(back.number(2, 0), -1e-300);

  EXPECT_THROW(writer.row({1}), std::invalid_argument);
  EXPECT_THROW(VnlogWriter(out, {"bad name"}), std::invalid_argument);
}

TEST(Vnlog, WriterWritesTextFields) {
  std::ostringstream out;
  VnlogWriter writer(out, {"filename", "x"});
  writer.row_texts({"a.png", "1.5"});
  writer.row_texts({"b.png", ""});
  EXPECT_EQ(out.str(), "# filename x\na.png 1.5\nb.png -\n");
  EXPECT_THROW(writer.row_texts({"with space", "1"}), std::invalid_argument);
  // It would read back as a comment.
  EXPECT_THROW(writer.row_texts({"board#1.png", "1"}), std::invalid_argument);
  // A form feed splits a field as a space does.
  EXPECT_THROW(writer.row_texts({"a\fb.png", "1"}), std::invalid_argument);
}

// What a field can hold is what reads back as one field; as_vnlog_field makes any text fit.
TEST(Vnlog, FieldsHoldNoWhitespaceNorHash) {
  for (const char* text : {"a b", "a\tb", "a\vb", "a\fb", "a\nb", "a#b"}) {
    EXPECT_FALSE(fits_vnlog_field(text)) << text;
    const std::string field = as_vnlog_field(text);
    EXPECT_EQ(field, "a_b");
    std::ostringstream out;
    VnlogWriter writer(out, {"name", "x"});
    writer.row_texts({field, "1"});
    std::istringstream in(out.str());
    VnlogReader reader(in, "written.vnl");
    ASSERT_TRUE(reader.next());
    EXPECT_EQ(reader.text(0), field);
  }
  EXPECT_TRUE(fits_vnlog_field("VMRImage0.jpg"));
  EXPECT_EQ(as_vnlog_field(""), "-");
}

}  // namespace
}  // namespace omnisfm::io
