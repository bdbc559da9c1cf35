// libFuzzer target: YAML scenes through loadSceneFromString, relative paths resolving in an empty
// directory. Generated meshes are capped at 1000 nodes (the default of mesh.max_nodes is 2 x 10^6)
// so that an input builds in milliseconds: the generators' size checks are the same code at any
// cap.
#include "FuzzInput.h"
#include "bcassim/scene/SceneLoader.h"

namespace {
const bcassim::SceneLimits kLimits{1000};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string yaml(reinterpret_cast<const char*>(data), size);
  const std::string directory = bcassim::fuzz::fuzzDirectory().string();
  bcassim::fuzz::expectOnlyInputErrors(
      [&] { bcassim::loadSceneFromString(yaml, "fuzz.yaml", directory, kLimits); });
  return 0;
}
