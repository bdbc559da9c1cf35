// Removes the temporary files of the tests once they have all run.
#include <gtest/gtest.h>

#include "TestFiles.h"

namespace {
class RemoveTempFiles : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(bcassim::test::processTempRoot(), ec);
  }
};
const ::testing::Environment* const kRemoveTempFiles =
    ::testing::AddGlobalTestEnvironment(new RemoveTempFiles);
}  // namespace
