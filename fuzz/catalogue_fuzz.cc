// libFuzzer harness: the catalogue opener and readers on damaged SQLite files (start the corpus
// from a real catalogue: scripts/fuzz.sh does). Rejections are InputError (bad state) or
// EnvironmentError; nothing may crash.
#include "catalogue/catalogue.h"
#include "fuzz_util.h"

#include <filesystem>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapstate;
  const auto file = fuzz::write_scratch("catalogue.sqlite", data, size);
  std::filesystem::remove(file.string() + "-wal");
  std::filesystem::remove(file.string() + "-shm");
  try {
    Catalogue catalogue(file, OpenMode::kReadOnly);
    catalogue.integrity_check();
    catalogue.read_all_checkpoints();
    catalogue.read_all_configurations();
    catalogue.read_all_transitions();
  } catch (const InputError&) {
  } catch (const EnvironmentError&) {
  }
  return 0;
}
