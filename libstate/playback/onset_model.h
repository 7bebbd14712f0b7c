// The contact-onset corners of a playback file (docs/playback.md, "Contact onset"), computed by
// hapstate-index from the file's other contents: for every zero configuration at a free
// check-point, the secant model of the touching configurations its transitions lead to.
#pragma once

#include "playback/format.h"
#include "playback/writer.h"

#include <vector>

namespace hapstate::playback {

// One OnsetCorner per configuration of `content` (contact: content.clearance filled; the
// fields are described with OnsetCorner). The neighbours of a free check-point's zero
// configuration are the touching configurations its transitions lead to, the nearest grid
// distance that has any (straight neighbours first).
std::vector<OnsetCorner> onset_corners(const Content& content);

}  // namespace hapstate::playback
