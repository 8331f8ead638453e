#include <gtest/gtest.h>

#include <fmt/format.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/file_lock.hpp"
#include "io/image.hpp"
#include "io/json_keys.hpp"
#include "io/output_files.hpp"
#include "io/parameters.hpp"
#include "io/text_file.hpp"
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

// Outputs on hostile file systems: a full disk, killed writers, concurrent runs.

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// A disk that fills up after `bytes`: RLIMIT_FSIZE with SIGXFSZ ignored makes every write past it
// fail with EFBIG, as ENOSPC would. Restored on destruction.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    previous_ = ::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    ::signal(SIGXFSZ, previous_);
  }

 private:
  rlimit saved_{};
  void (*previous_)(int) = nullptr;
};

std::vector<float> noise(int w, int h) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0, 1);
  std::vector<float> rgb(static_cast<std::size_t>(w) * h * 3);
  for (float& v : rgb) v = unit(rng);
  return rgb;
}

// OpenImageIO's PNG writer reports success on a full disk; the image lands
// truncated under its name. Every image format goes through write_file_atomically now.
std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// An output given as a symbolic link is written through it: the link stays a link and its file
// gets the contents (renaming onto the link replaced it with a plain file, and the file it named
// kept the old contents). Through a chain of links, relative ones, a dangling link (the file it
// names is made), and for staged outputs; a loop of links is refused, naming the path.
TEST(AtomicFile, OutputsAreWrittenThroughSymbolicLinks) {
  const auto dir = fresh_dir("splatcl_atomic_links");
  fs::create_directories(dir / "data");
  {
    std::ofstream(dir / "data" / "real.txt") << "old";
  }
  fs::create_symlink("data/real.txt", dir / "link.txt");  // relative to the link's directory
  fs::create_symlink(dir / "link.txt", dir / "chain.txt");
  write_file_atomically((dir / "chain.txt").string(), "new");
  EXPECT_TRUE(fs::is_symlink(dir / "chain.txt"));
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_EQ(read_all(dir / "data" / "real.txt"), "new");
  EXPECT_EQ(written_through((dir / "chain.txt").string()), (dir / "data" / "real.txt").string());

  fs::create_symlink("data/made.txt", dir / "dangling.txt");
  write_file_atomically((dir / "dangling.txt").string(), "made");
  EXPECT_TRUE(fs::is_symlink(dir / "dangling.txt"));
  EXPECT_EQ(read_all(dir / "data" / "made.txt"), "made");

  fs::create_symlink("data/staged.ply", dir / "staged-link.ply");
  check_output_file((dir / "staged-link.ply").string(), "-o");
  {
    StagedOutputs outputs;
    const std::string staged = outputs.stage((dir / "staged-link.ply").string());
    EXPECT_EQ(fs::path(staged).parent_path(), dir / "data");  // beside the file, so the rename is atomic
    outputs.write((dir / "staged-link.ply").string(), [](const std::string& name) { std::ofstream(name) << "ply"; });
    outputs.commit();
  }
  EXPECT_TRUE(fs::is_symlink(dir / "staged-link.ply"));
  EXPECT_EQ(read_all(dir / "data" / "staged.ply"), "ply");
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir / "data")) ++entries;
  EXPECT_EQ(entries, 3u) << "no temporaries left";

  // Two dangling links to one missing file are one output (the file got only the last write).
  fs::create_symlink("data/same", dir / "a.ply");
  fs::create_symlink("data/same", dir / "b.json");
  EXPECT_THROW(check_distinct_outputs({{"-o", (dir / "a.ply").string()}, {"--stats", (dir / "b.json").string()}}), Error);
  // A killed run's staged file beside a link's file keeps the link's extension: it is cleared too.
  fs::create_symlink("data/real.bin", dir / "bin-link.ply");
  std::ofstream(dir / "data" / "real.bin.partial999999999.ply") << "half";
  remove_dead_temporaries((dir / "bin-link.ply").string());
  EXPECT_FALSE(fs::exists(dir / "data" / "real.bin.partial999999999.ply"));

  fs::create_symlink("loop-b.txt", dir / "loop-a.txt");
  fs::create_symlink("loop-a.txt", dir / "loop-b.txt");
  try {
    write_file_atomically((dir / "loop-a.txt").string(), "x");
    FAIL() << "a loop of links was written";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("loop-a.txt: too many levels of symbolic links"), std::string::npos) << e.what();
  }
}

TEST(ImageOutput, FullDiskIsAWriteFailureWithNothingAtTheTarget) {
  const auto dir = fresh_dir("splatcl_io_full_disk");
  for (const char* name : {"frame.png", "frame.exr"}) {
    const std::string path = (dir / name).string();
    std::string message;
    {
      const FileSizeLimit full(4096);  // the 64x64 noise image needs several times that
      message = error_of([&] { write_image_rgb(path, 64, 64, noise(64, 64)); });
    }
    EXPECT_EQ(message, "cannot write " + path + ": write failed (disk full?)") << name;
    EXPECT_FALSE(fs::exists(path)) << name;
    EXPECT_TRUE(fs::is_empty(dir)) << "a temporary was left behind for " << name;
  }
  // The same image with room to spare is complete and readable.
  const std::string path = (dir / "frame.png").string();
  write_image_rgb(path, 64, 64, noise(64, 64));
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, 64);
  std::vector<unsigned char> pixels(64 * 64 * 3);
  EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
}

TEST(ImageOutput, AnEarlierImageSurvivesAFailedWrite) {
  const auto dir = fresh_dir("splatcl_io_keep_old");
  const std::string path = (dir / "frame.png").string();
  write_file_atomically(path, "earlier");
  {
    const FileSizeLimit full(4096);
    EXPECT_NE(error_of([&] { write_image_rgb(path, 64, 64, noise(64, 64)); }), "(no error)");
  }
  std::ifstream in(path);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "earlier");
}

// A killed writer leaves PATH.tmpPID; the next command writing PATH removes those
// of processes that no longer exist and keeps a live process's.
TEST(AtomicFile, TemporariesOfDeadProcessesAreRemovedLiveOnesKept) {
  const auto dir = fresh_dir("splatcl_io_dead_temporaries");
  const std::string path = (dir / "model.csm").string();
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);  // its pid now belongs to no process
  const std::string dead = path + ".tmp" + std::to_string(child);
  const std::string dead_staged = path + ".partial" + std::to_string(child) + ".csm";
  // A staged output's own temporary (commands with several outputs stage each, then write the
  // staged file atomically): it survived every later run.
  const std::string dead_staged_temporary = dead_staged + ".tmp" + std::to_string(child);
  const std::string live = path + ".tmp" + std::to_string(::getpid());
  const std::string live_staged_temporary = path + ".partial" + std::to_string(::getpid()) + ".csm.tmp" + std::to_string(::getpid());
  const std::string other = (dir / "model.csm.json.tmp1").string();  // another file's: not ours to remove
  const std::string not_a_temporary = path + ".partial" + std::to_string(child) + ".csm.tmp";
  for (const auto& p : {dead, dead_staged, dead_staged_temporary, live, live_staged_temporary, other, not_a_temporary})
    std::ofstream(p) << "partial";
  remove_dead_temporaries(path);
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_FALSE(fs::exists(dead_staged));
  EXPECT_FALSE(fs::exists(dead_staged_temporary));
  EXPECT_TRUE(fs::exists(live_staged_temporary));
  EXPECT_TRUE(fs::exists(not_a_temporary));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
}

// Outputs are checked by writing, so a full file system fails before the work.
TEST(OutputFiles, AFullFileSystemFailsTheCheckBeforeAnyWork) {
  const auto dir = fresh_dir("splatcl_io_probe");
  const std::string path = (dir / "out.ply").string();
  EXPECT_NO_THROW(check_output_file(path, "-o"));
  std::string message;
  {
    const FileSizeLimit full(0);
    message = error_of([&] { check_output_file(path, "-o"); });
  }
  EXPECT_EQ(message, "cannot write -o " + path + ": directory " + dir.string() + " is not writable (File too large)");
  EXPECT_TRUE(fs::is_empty(dir));
}

// A file name the file system cannot hold with the temporary names' suffix is refused before any
// work (it failed with "File name too long" when written, after it).
TEST(OutputFiles, AFileNameTooLongForTheTemporaryNamesIsRefused) {
  const auto dir = fresh_dir("splatcl_io_long_name");
  const long name_max = ::pathconf(dir.c_str(), _PC_NAME_MAX);
  if (name_max <= 0) GTEST_SKIP() << "the file system states no name limit";
  // NAME.partialPID.ply.tmpPID: the extension twice.
  const std::string fits = std::string(static_cast<std::size_t>(name_max) - kTemporaryNameBytes - 8, 'a') + ".ply";
  EXPECT_NO_THROW(check_output_file((dir / fits).string(), "-o"));
  const std::string longer = "a" + fits;
  const std::string message = error_of([&] { check_output_file((dir / longer).string(), "-o"); });
  EXPECT_EQ(message, fmt::format("cannot write -o {}: the file name is {} bytes long; this file system allows {}, and splatcl's temporary "
                                 "names add {}",
                                 (dir / longer).string(), longer.size(), name_max, kTemporaryNameBytes + 4));
  // The longest name that passes can be written atomically through a staged name.
  StagedOutputs outputs;
  outputs.stage((dir / fits).string());
  outputs.write((dir / fits).string(), [](const std::string& name) { std::ofstream(name) << "ply"; });
  outputs.commit();
  EXPECT_EQ(read_all(dir / fits), "ply");
}

TEST(OutputFiles, PathsWithinADirectory) {
  EXPECT_TRUE(path_within(comparable_path("/a/b/c"), comparable_path("/a/b")));
  EXPECT_TRUE(path_within(comparable_path("/a/b"), comparable_path("/a/b/")));
  EXPECT_TRUE(path_within(comparable_path("/a/b/../b"), comparable_path("/a/b")));
  EXPECT_FALSE(path_within(comparable_path("/a/bc"), comparable_path("/a/b")));
  EXPECT_FALSE(path_within(comparable_path("/a"), comparable_path("/a/b")));
}

// A key locked by one process is refused to another, which is told its pid; the
// lock goes when the holder ends, however it ends.
TEST(KeyLocks, ASecondProcessIsRefusedUntilTheFirstEnds) {
  const auto dir = fresh_dir("splatcl_io_locks");
  const std::string path = (dir / ".lock").string();
  int ready[2], done[2];
  ASSERT_EQ(::pipe(ready), 0);
  ASSERT_EQ(::pipe(done), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    KeyLocks locks(path);
    char c = locks.try_lock("bunny") == 0 ? 'y' : 'n';
    (void)!::write(ready[1], &c, 1);
    (void)!::read(done[0], &c, 1);
    ::_exit(0);
  }
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  ASSERT_EQ(c, 'y');
  {
    KeyLocks locks(path);
    EXPECT_EQ(locks.try_lock("bunny"), child);
    EXPECT_EQ(locks.try_lock("dragon"), 0);  // other keys are free
  }
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  KeyLocks locks(path);
  EXPECT_EQ(locks.try_lock("bunny"), 0);
}

TEST(JsonKeys, TheFirstUnknownKeyIsNamed) {
  const auto j = nlohmann::json::parse(R"({"position": [0, 0, 0], "colour": [1, 0, 0]})");
  EXPECT_EQ(unknown_key(j, {"position", "color"}), "colour");
  EXPECT_EQ(unknown_key(j, {"position", "colour"}), std::nullopt);
  EXPECT_EQ(key_list({"a", "b"}), "a, b");
}

// A key or value with a line break (the fuzzer's present_scene finding) keeps the error on one line.
TEST(JsonKeys, KeysAndValuesWithControlCharactersArePrintedOnOneLine) {
  const auto j = nlohmann::json::parse(R"({"posi\ntion": 1, "tab\there\u0001": 2})");
  EXPECT_EQ(unknown_key(j, {"tab\there\x01"}), "posi\\ntion");
  EXPECT_EQ(printable("tab\there\x01\r"), "tab\\there\\x01\\r");
  EXPECT_EQ(shown_value(nlohmann::json("a\nb")), "'a\\nb'");
  EXPECT_EQ(printable("plain ascii and UTF-8 \u00e9"), "plain ascii and UTF-8 \u00e9");
}

// A directory is reported as a directory, not as a missing file or bad JSON.
TEST(TextFile, ADirectoryOrAMissingFileIsNamedAsSuch) {
  const auto dir = fresh_dir("splatcl_io_text");
  EXPECT_EQ(error_of([&] { read_text_file(dir.string(), "scene"); }), "cannot read scene " + dir.string() + ": it is a directory");
  const std::string missing = (dir / "missing.json").string();
  EXPECT_EQ(error_of([&] { read_text_file(missing, "scene"); }), "cannot read scene " + missing + ": No such file or directory");
}

// Well-formed UTF-8 only, as the JSON reader takes it (the CSV readers' check).
TEST(TextFile, Utf8IsCheckedAsTheJsonReaderDoes) {
  for (const char* good : {"", "plain ascii", "mod\xC3\xA8le", "\xE2\x82\xAC", "\xF0\x9F\x98\x80", "\xF4\x8F\xBF\xBF", "\xED\x9F\xBF"})
    EXPECT_TRUE(is_utf8(good)) << good;
  // A stray continuation byte, a cut sequence, overlong forms, a surrogate, beyond U+10FFFF, 0xFF.
  for (const char* bad : {"\x80", "a\xC3", "\xE2\x82", "\xC0\xAF", "\xE0\x80\xAF", "\xF0\x80\x80\xAF", "\xED\xA0\x80", "\xF4\x90\x80\x80",
                          "\xFF", "\xC3\x28"})
    EXPECT_FALSE(is_utf8(bad)) << bad;
}

}  // namespace
}  // namespace splatcl
