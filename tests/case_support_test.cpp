// The harness's scratch directory (validation/case_support.h): the ξ files
// the appearance cases write for the reader under test are gone after the run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "validation/case_support.h"

namespace ft {
namespace {

TEST(ScratchDirectory, IsCreatedAndRemovedWithItsFiles) {
  std::filesystem::path dir;
  {
    const ScratchDirectory scratch("fibertwin-scratch-test");
    dir = scratch.path();
    ASSERT_TRUE(std::filesystem::is_directory(dir));
    EXPECT_EQ(dir.parent_path(), std::filesystem::temp_directory_path());
    std::filesystem::create_directories(dir / "sub");
    std::ofstream(dir / "sub" / "xi.bin") << "bytes";
    ASSERT_TRUE(std::filesystem::exists(dir / "sub" / "xi.bin"));
  }
  EXPECT_FALSE(std::filesystem::exists(dir)) << dir;
}

}  // namespace
}  // namespace ft
