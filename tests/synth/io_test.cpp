// synth/io.h: write_file_atomic from several threads at once onto one path (two cases
// of a run storing the same Cycles image in the render cache).
#include "synth/io.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "synth/temp_folder.h"

namespace grapebench {
namespace {

TEST(WriteFileAtomic, ThreadsWritingOnePathEachLeaveAWholeFileAndNoTemporary) {
  const TempFolder t("grapebench-io-test");
  const auto path = t.path / "entry";
  const std::string a(1 << 16, 'a'), b(1 << 16, 'b');
  std::atomic<int> errors{0};
  const auto writer = [&](const std::string* bytes) {
    for (int k = 0; k < 200; ++k) {
      try {
        write_file_atomic(path, *bytes);
      } catch (const std::exception&) {
        ++errors;  // with one temporary name a process, the slower rename failed
      }
    }
  };
  std::thread x(writer, &a), y(writer, &b);
  x.join(), y.join();
  EXPECT_EQ(errors.load(), 0);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_TRUE(text.str() == a || text.str() == b) << text.str().size() << " bytes, mixed";
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(t.path), std::filesystem::directory_iterator()), 1);
}

}  // namespace
}  // namespace grapebench
