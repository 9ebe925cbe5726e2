// The running test's own folder in the temporary folder, so that tests never meet on a file
// name: not two tests of one program, and not two copies of one test program run at once
// (ctest -j, a second checkout's run, two developers on one machine).
#pragma once

#include <stdlib.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>

namespace surftrace::test {

namespace detail {

// The folder of the test that asked last. Made with mkdtemp (a name no other process holds),
// removed when another test asks for its own and when the program ends, unless that test failed:
// then it stays, for a look at what the test wrote (its messages name those files). Only the
// process that made it removes it: a forked child that exits normally leaves its parent's
// files alone.
class CurrentTestDir {
 public:
  CurrentTestDir() = default;
  CurrentTestDir(const CurrentTestDir&) = delete;
  CurrentTestDir& operator=(const CurrentTestDir&) = delete;
  ~CurrentTestDir() { remove(); }

  std::filesystem::path forTest(const ::testing::TestInfo* info, const std::string& test) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!path_.empty() && info_ == info && test_ == test) return path_;
    remove();
    const std::filesystem::path base = std::filesystem::temp_directory_path();
    std::string name = (base / ("surftrace_" + test + "_XXXXXX")).string();
    if (::mkdtemp(name.data()) == nullptr)
      throw std::runtime_error("cannot make a folder " + name + " for the test's files: " + std::strerror(errno) +
                               " (set TMPDIR to a writable folder)");
    path_ = name;
    info_ = info;
    test_ = test;
    owner_ = ::getpid();
    return path_;
  }

 private:
  void remove() {
    if (path_.empty() || ::getpid() != owner_) return;
    if (info_ && info_->result()->Failed()) {
      std::fprintf(stderr, "%s failed: its files are kept in %s\n", test_.c_str(), path_.c_str());
    } else {
      std::error_code ignored;  // a folder that cannot be removed is no reason to fail a test
      std::filesystem::remove_all(path_, ignored);
    }
    path_.clear();
  }

  std::mutex mutex_;
  std::filesystem::path path_;
  const ::testing::TestInfo* info_ = nullptr;  // gtest's, alive until the program ends
  std::string test_;
  ::pid_t owner_ = 0;
};

}  // namespace detail

// The running test's own folder: surftrace_<Suite>.<Test>_XXXXXX under $TMPDIR (else /tmp),
// named after the test so that a folder left by a killed run says whose it is. The same folder
// on every call within one test; a new one for the next test.
inline std::filesystem::path testTempDir() {
  static detail::CurrentTestDir current;
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string test = info ? std::string(info->test_suite_name()) + "." + info->name() : "outside_a_test";
  std::replace(test.begin(), test.end(), '/', '_');  // parameterised tests: Cases/Suite.Name/3
  return current.forTest(info, test);
}

// An empty folder `name` inside testTempDir(), emptied again if the test asks twice.
inline std::filesystem::path freshTempDir(const std::string& name) {
  const std::filesystem::path dir = testTempDir() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace surftrace::test
