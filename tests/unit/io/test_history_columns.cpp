// history.csv's columns declared once (io/history_columns.hpp): the header and each row
// are made from the table, with the widths and formats of before; docs/cases.md lists
// the columns as the table does.
#include "cases/builtin_cases.hpp"
#include "io/history_columns.hpp"
#include "io/run_output.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <fstream>
#include <sstream>

namespace vpc {
namespace {

namespace fs = std::filesystem;

TEST(HistoryColumns, HeaderAndRowsComeFromTheTable) {
  TimeStepper s(load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem);
  const StepReport r = s.step();
  const std::vector<std::string> names = history_column_names(s.problem(), s.part());
  ASSERT_GE(names.size(), history_columns().size());
  for (std::size_t i = 0; i < history_columns().size(); ++i) EXPECT_EQ(names[i], history_columns()[i].name);
  EXPECT_EQ(history_header(s.problem(), s.part()), fmt::format("{}\n", fmt::join(names, ",")));
  const std::vector<HistoryValue> row = history_values(r);
  ASSERT_EQ(row.size(), names.size());
  EXPECT_EQ(row[0].text(), "1");
  EXPECT_EQ(row[1].value, r.t);
  // The formats of the file: integers, 17 digits, residuals with 4.
  EXPECT_EQ((HistoryValue{3, ColumnFormat::integer}.text()), "3");
  EXPECT_EQ((HistoryValue{0.1, ColumnFormat::exact}.text()), "0.10000000000000001");
  EXPECT_EQ((HistoryValue{1.23456e-9, ColumnFormat::residual}.text()), "1.235e-09");
  std::string line;
  for (const HistoryValue& v : row) {
    if (!line.empty()) line += ',';
    line += v.text();
  }
  EXPECT_EQ(history_row(r), line + "\n");
}

/// The markdown table of `columns`, as docs/cases.md has it.
std::string table_of(std::span<const HistoryColumn> columns) {
  std::string expected = "| column | written as | meaning |\n|---|---|---|\n";
  for (const HistoryColumn& c : columns)
    expected += fmt::format("| `{}` | {} | {} |\n", c.name,
                            c.format == ColumnFormat::integer ? "integer"
                            : c.format == ColumnFormat::exact ? "17 digits"
                                                              : "4 digits",
                            c.meaning);
  return expected;
}

// docs/cases.md's tables of the columns (every run's; a frictional run's) are the tables
// (paste the expected text there when a column is added).
TEST(HistoryColumns, DocsListEveryColumn) {
  std::ifstream in(fs::path(VPC_TEST_DATA_DIR) / "../../docs/cases.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  for (const auto& [name, columns] : {std::pair{"history columns", history_columns()},
                                      std::pair{"friction columns", friction_columns()},
                                      std::pair{"tresca columns", open_friction_columns()},
                                      std::pair{"adapt columns", adapt_columns()}}) {
    const std::string expected = table_of(columns);
    const std::string begin = fmt::format("<!-- begin {} -->\n", name), end = fmt::format("<!-- end {} -->", name);
    const auto a = doc.find(begin), b = doc.find(end);
    ASSERT_TRUE(a != std::string::npos && b != std::string::npos) << "docs/cases.md: no markers " << name;
    EXPECT_EQ(doc.substr(a + begin.size(), b - a - begin.size()), expected)
        << "docs/cases.md between the markers " << name << " should read:\n"
        << expected;
  }
}

}  // namespace
}  // namespace vpc
