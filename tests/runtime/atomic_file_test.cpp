#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/atomic_file.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const char* name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(AtomicFile, WritesContentsAndLeavesNoTemporary) {
  const auto dir = fresh_dir("splatcl_atomic_ok");
  const auto path = (dir / "out.txt").string();
  write_file_atomically(path, "hello");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "hello");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(AtomicFile, FailedWriterKeepsOldFileAndRemovesTemporary) {
  const auto dir = fresh_dir("splatcl_atomic_fail");
  const auto path = (dir / "out.txt").string();
  write_file_atomically(path, "old");
  EXPECT_THROW(write_atomically(path,
                                [](const std::string& temp) {
                                  std::ofstream(temp) << "partial";
                                  throw std::runtime_error("interrupted");
                                }),
               Error);
  std::ifstream in(path);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "old");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(AtomicFile, MissingDirectoryIsAClearError) {
  try {
    write_file_atomically("/nonexistent-splatcl-dir/out.txt", "x");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-splatcl-dir"), std::string::npos);
  }
}

}  // namespace
}  // namespace splatcl
