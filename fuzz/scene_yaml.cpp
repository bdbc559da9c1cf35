// libFuzzer target: YAML scenes through loadSceneFromString, relative paths resolving in an empty
// directory.
#include "FuzzInput.h"
#include "bcassim/scene/SceneLoader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string yaml(reinterpret_cast<const char*>(data), size);
  const std::string directory = bcassim::fuzz::fuzzDirectory().string();
  bcassim::fuzz::expectOnlyInputErrors(
      [&] { bcassim::loadSceneFromString(yaml, "fuzz.yaml", directory); });
  return 0;
}
