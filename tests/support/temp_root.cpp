// Each test process keeps its temporary files in one directory of its own, removed when its tests end:
// the tests write under std::filesystem::temp_directory_path() (and the command-line runs they start
// inherit it), which reads TMPDIR; so a run of the tiers leaves nothing behind in /tmp, and two test
// processes never share a fixed name there.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>

namespace {

class TemporaryRoot : public ::testing::Environment {
 public:
  void SetUp() override {
    const char* outer = std::getenv("TMPDIR");
    if (outer) outer_ = outer;
    std::string pattern = (std::filesystem::temp_directory_path() / "vpcontact-test-XXXXXX").string();
    if (!mkdtemp(pattern.data())) return;  // (the tests then use the system's directory, as before)
    root_ = pattern;
    setenv("TMPDIR", root_.c_str(), 1);
  }
  void TearDown() override {
    if (root_.empty()) return;
    if (outer_) setenv("TMPDIR", outer_->c_str(), 1);
    else unsetenv("TMPDIR");
    std::error_code ignored;
    std::filesystem::remove_all(root_, ignored);
  }

 private:
  std::string root_;
  std::optional<std::string> outer_;
};

// Registered before gtest_main's main() runs (GoogleTest's documented way for a global environment).
[[maybe_unused]] ::testing::Environment* const temporary_root = ::testing::AddGlobalTestEnvironment(new TemporaryRoot);

}  // namespace
