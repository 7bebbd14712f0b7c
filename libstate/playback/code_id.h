// The identity of the playback runtime's code: 64 bits of the SHA-256 of its sources
// (libstate/playback/, the content hash and the point-triangle distance it compiles in, and
// include/hapstate/playback.h), computed at build time by cmake/PlaybackCodeId.cmake. A
// certificate records the id of the cursor that measured it (docs/certificate.md): one measured by
// other code is stale, as is one measured on another playback file.
#pragma once

#include <cstdint>

namespace hapstate {

std::uint64_t playback_code_id();

}  // namespace hapstate
