// The contact-onset corners of a playback file (docs/playback.md, "Contact onset"), computed by
// hapstate-index from the file's other contents: every configuration's depth model (the force
// against the sphere's depth into the rest body, from its force and stiffness), and for a free
// check-point's zero configuration the secant model of the touching configurations its transitions
// lead to.
#pragma once

#include "playback/format.h"
#include "playback/writer.h"

#include <vector>

namespace hapstate::playback {

// One OnsetCorner per configuration of `content` (contact: content.clearance filled; the
// fields are described with OnsetCorner).
std::vector<OnsetCorner> onset_corners(const Content& content);

}  // namespace hapstate::playback
