// libFuzzer harness: one mesh reader (chosen at build time by HAPSTATE_FUZZ_READER, see
// CMakeLists.txt), then the validation every loaded mesh goes through.
#include "fuzz_util.h"
#include "mesh/readers.h"
#include "mesh/validate.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapstate;
  const std::string_view text = fuzz::as_text(data, size);
  std::string format;
  try {
    RawMesh raw;
#if HAPSTATE_FUZZ_READER == 1
    raw = read_msh(text, "fuzz.msh", &format);
#elif HAPSTATE_FUZZ_READER == 2
    raw = read_vtk_legacy(text, "fuzz.vtk", &format);
#elif HAPSTATE_FUZZ_READER == 3
    raw = read_vtu(text, "fuzz.vtu", &format);
#elif HAPSTATE_FUZZ_READER == 4
    raw = read_medit(text, "fuzz.mesh");
#elif HAPSTATE_FUZZ_READER == 5
    // TetGen: the input split at the first NUL into the .node and the .ele file.
    const std::size_t cut = text.find('\0');
    const std::string_view node = text.substr(0, cut);
    const std::string_view ele =
        cut == std::string_view::npos ? std::string_view() : text.substr(cut + 1);
    fuzz::write_scratch("fuzz.node", reinterpret_cast<const std::uint8_t*>(node.data()),
                        node.size());
    fuzz::write_scratch("fuzz.ele", reinterpret_cast<const std::uint8_t*>(ele.data()), ele.size());
    raw = read_tetgen(fuzz::scratch("fuzz.node"));
#else
#error "HAPSTATE_FUZZ_READER must be 1..5"
#endif
    MeshReport report;
    validate_mesh(std::move(raw), &report);
  } catch (const InputError&) {
  }
  return 0;
}
