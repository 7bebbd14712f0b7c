#include "util/version.h"

namespace hapstate {
const char* version_string() { return "0.1.0"; }
}  // namespace hapstate
