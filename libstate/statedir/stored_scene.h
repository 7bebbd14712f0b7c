// The scene as the state directory keeps it: the text hapstate-import stored in the catalogue
// (SceneRecord), read and parsed the one way every later reader needs it.
#pragma once

#include "catalogue/catalogue.h"
#include "scene/scene.h"
#include "statedir/state_dir.h"

namespace hapstate {

// The stored scene record; throws InputError naming the catalogue if none is stored.
SceneRecord read_stored_scene(Catalogue& catalogue, const StateDir& dir);

// The stored scene parsed: its files are not checked (the problem is stored with it), relative
// paths resolve against the state directory, and messages name the catalogue. With
// `require_probe` false a scene without [probe] and [grid] is accepted.
Scene parse_stored_scene(const SceneRecord& record, const StateDir& dir, bool require_probe = true);

}  // namespace hapstate
