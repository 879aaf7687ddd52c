// Files named from outside: never blocked on, never read past their cap (issue 39: a
// scene path or case file that was a FIFO blocked forever; a FIFO was "no such file").
#include "synth/read_regular_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "synth/config.h"

namespace grapebench {
namespace {

namespace fs = std::filesystem;

std::string error_of(const fs::path& p, std::size_t cap) {
  try {
    (void)read_regular_file(p, cap);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ReadRegularFile, SpecialFilesAreRefusedAtOnceSayingWhatTheyAre) {
  const fs::path dir = fs::temp_directory_path() / ("gb-read-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "folder");
  ASSERT_EQ(mkfifo((dir / "fifo").c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", dir / "zero");
  std::ofstream(dir / "ok.yaml") << "seed: 5\n";
  EXPECT_EQ(read_regular_file(dir / "ok.yaml", 100), "seed: 5\n");
  EXPECT_NE(error_of(dir / "fifo", 100).find("fifo: a FIFO (named pipe), not a regular file"), std::string::npos);
  EXPECT_NE(error_of(dir / "zero", 100).find("zero: a character device"), std::string::npos);
  EXPECT_NE(error_of(dir / "folder", 100).find("folder: a folder"), std::string::npos);
  EXPECT_NE(error_of(dir / "missing", 100).find("missing: no such file"), std::string::npos);
  EXPECT_NE(error_of(dir / "ok.yaml", 4).find("8 bytes, more than the 4 bytes allowed"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace grapebench
