// The one libFuzzer executable for every starnav parser. It is called through a link named after
// the target (build/fuzz/fuzz_png -> starnav_fuzz; scripts/fuzz.sh uses the links), or with the
// environment variable STARNAV_FUZZ_TARGET set. One executable instead of one per target: each
// would link the whole instrumented library, which cost the sanitizer build minutes.
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "fuzz_entry.hpp"

namespace {

const starnav::fuzz::Target* g_target = nullptr;

// Where a PNG starts in the target's input, for the CRC-fixing mutator; npos: the target has none.
std::size_t png_offset(std::string_view target, std::string_view input) {
  if (target == "fuzz_png") return 0;
  if (target == "fuzz_elevation_yaml") {
    const std::size_t at = input.find(starnav::fuzz::kFileSeparator);
    return at == std::string_view::npos ? at : at + starnav::fuzz::kFileSeparator.size();
  }
  return std::string_view::npos;
}

std::string_view target_name(const char* argv0) {
  if (const char* env = std::getenv("STARNAV_FUZZ_TARGET"); env != nullptr && *env != '\0') return env;
  const std::string_view path(argv0);
  const std::size_t slash = path.rfind('/');
  return slash == std::string_view::npos ? path : path.substr(slash + 1);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** argv) {
  const std::string_view name = target_name((*argv)[0]);
  g_target = starnav::fuzz::find_target(name);
  if (g_target == nullptr) {
    std::fprintf(stderr,
                 "starnav fuzz: error: no target named '%.*s' (call the executable through a link named after the "
                 "target, e.g. fuzz_png, or set STARNAV_FUZZ_TARGET; scripts/fuzz.sh list)\n",
                 static_cast<int>(name.size()), name.data());
    std::exit(2);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return starnav::fuzz::run_one(g_target->run, data, size);
}

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

// PNG chunks carry a CRC that libpng checks, so nearly every byte-level mutation of a PNG would only
// reach "CRC error": for the targets whose input holds a PNG, the CRCs are recomputed after most
// mutations (inputs with a bad CRC are still produced, one mutation in eight). Other targets get
// libFuzzer's mutations unchanged.
extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  size = LLVMFuzzerMutate(data, size, max_size);
  if (seed % 8 == 0) return size;
  const std::size_t start = png_offset(g_target->name, std::string_view(reinterpret_cast<const char*>(data), size));
  if (start == std::string_view::npos || start > size) return size;
  starnav::fuzz::fix_png_crcs(data + start, size - start);
  return size;
}
