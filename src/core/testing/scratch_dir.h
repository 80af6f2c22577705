// A directory of files for one test, removed after it.
#ifndef RRR_CORE_TESTING_SCRATCH_DIR_H_
#define RRR_CORE_TESTING_SCRATCH_DIR_H_

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace rrr::testing {

// An empty directory under the system's temporary one, named for the
// process and the running test, so tests run in parallel never share one;
// it is removed with what it holds when this is destroyed. Construct it in
// a test or a fixture (it names the running test).
class ScratchDir {
 public:
  ScratchDir()
      : path_(std::filesystem::temp_directory_path() /
              ("rrr_" + std::to_string(::getpid()) + "_" + TestName())) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  // The path of file `name` in this directory.
  std::string File(const std::string& name) const {
    return (path_ / name).string();
  }

 private:
  static std::string TestName() {
    const ::testing::TestInfo* test =
        ::testing::UnitTest::GetInstance()->current_test_info();
    return std::string(test->test_suite_name()) + "_" + test->name();
  }

  std::filesystem::path path_;
};

}  // namespace rrr::testing

#endif  // RRR_CORE_TESTING_SCRATCH_DIR_H_
