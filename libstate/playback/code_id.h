// The identity of the playback runtime's code: 64 bits of the SHA-256 of its sources
// (libstate/playback/, the util/ files it compiles in or includes, include/hapstate/playback*.h
// and error.h; not the compiler's flags), computed at build time by cmake/PlaybackCodeId.cmake. A
// certificate records the id of the cursor that measured it (docs/certificate.md): one measured by
// other code is stale, as is one measured on another playback file.
#pragma once

#include <cstdint>

namespace hapstate {

std::uint64_t playback_code_id();

}  // namespace hapstate
