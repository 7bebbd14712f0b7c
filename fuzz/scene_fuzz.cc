// libFuzzer harness: the scene parser (TOML syntax, every key's checks), without the file checks.
#include "fuzz_util.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapstate;
  SceneParseOptions options;
  options.check_files = false;
  try {
    parse_scene(std::string(fuzz::as_text(data, size)), "fuzz.toml", options);
  } catch (const InputError&) {
  }
  return 0;
}
