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

// Sections 24-26 of `content` (content.clearance filled): for every cell where the cursor may
// blend in the depth model (a corner within the onset band plus a cell diagonal of the onset,
// and not every corner clear by a diagonal), the rest triangles among `triangles` (9 doubles
// each, mesh units) that can be the nearest to a point of the cell; `radius` the sphere's. None
// when the radius is under 3/4 of the smallest spacing (the sphere's centre could then be inside
// the rest body in the onset band, where the distance to the triangles is not the clearance).
void add_onset_triangles(Content* content, const std::vector<double>& triangles, double radius);

}  // namespace hapstate::playback
